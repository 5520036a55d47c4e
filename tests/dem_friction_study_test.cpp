// The friction side study (scripts/dem_reference.sh, stage friction;
// dem/collapse/results_mu_r0.6 and results_mu_r0.15): the DEM's grains with
// their rolling friction 0.6 and 0.15 for 0.3, each calibrated on the pile,
// the inclined layers and the erodible bed alone, and their tubes of aspect
// ratio 0.5, 1 and 2. The model takes each calibration (calibrated_flow)
// and nothing from the tubes: does its run-out follow the material's
// friction as the DEM's does?
// docs/fast_flows.md, "A rougher material, and a smoother one".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/soil_table.h"
#include "report/dem_columns.h"
#include "report/perf_report_parts.h"

namespace skidsim::report::perf {
namespace {

// dem_sand's flow law is its calibration's: the soil table and
// calibration/material.csv hold the same angles (within the table's
// rounding), so a second calibration read the same way is the same model.
TEST(DemFrictionStudy, DemSandsFlowLawIsItsCalibrations) {
  const terrain::SoilFlowParameters sand = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  const terrain::SoilFlowParameters read = calibrated_flow(columns_material(repository_dem_dir(), "results"), sand);
  EXPECT_NEAR(read.repose_angle_deg, sand.repose_angle_deg, 0.02);
  EXPECT_NEAR(read.stop_angle_deg, sand.stop_angle_deg, 0.02);
  EXPECT_NEAR(read.flowing_friction_angle_deg, sand.flowing_friction_angle_deg, 0.02);
  EXPECT_NEAR(read.thin_layer_friction_angle_deg, sand.thin_layer_friction_angle_deg, 0.02);
  EXPECT_NEAR(read.thin_layer_decay_grains, sand.thin_layer_decay_grains, 0.002);
  EXPECT_NEAR(read.bed_start_angle_deg, sand.bed_start_angle_deg, 0.02);
  EXPECT_NEAR(read.rate_friction_angle_deg, sand.rate_friction_angle_deg, 0.02);
  EXPECT_NEAR(read.rate_friction_i0, sand.rate_friction_i0, 0.0002);
  EXPECT_DOUBLE_EQ(read.grain_diameter_m, sand.grain_diameter_m);
  for (const FrictionStudyMaterial& m : kFrictionStudy)
    EXPECT_EQ(columns_material(repository_dem_dir(), m.results), repository_dem_dir() / "collapse" / m.results / "material.csv");
}

// One material of the friction study against its DEM at 10 and 5 cm,
// beside the calibrated material's: each tube's model and DEM in both.
struct StudyRun {
  std::string name;
  DemColumn dem, calibrated_dem;
  terrain::CollapseRun model, calibrated_model;
};

std::vector<StudyRun> study(const FrictionStudyMaterial& m) {
  const terrain::SoilFlowParameters sand = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  const terrain::SoilFlowParameters soil = calibrated_flow(columns_material(repository_dem_dir(), m.results), sand);
  std::printf("[ measured ] rolling friction %g: repose %.2f, stop %.2f, flowing friction %.2f, thin layers %.2f over "
              "%.2f grains, the bed's start angle %.2f deg\n",
              m.rolling_friction, soil.repose_angle_deg, soil.stop_angle_deg, soil.flowing_friction_angle_deg,
              soil.thin_layer_friction_angle_deg, soil.thin_layer_decay_grains, soil.bed_start_angle_deg);
  const std::vector<DemColumn> base = read_dem_columns(repository_dem_dir()), dem = read_dem_columns(repository_dem_dir(), m.results);
  std::vector<StudyRun> out;
  for (double cell : {0.1, 0.05}) {
    for (const DemColumn& d : dem) {
      const auto b =
          std::find_if(base.begin(), base.end(), [&](const DemColumn& c) { return standing_tube(c) && c.aspect == d.aspect; });
      if (b == base.end()) throw std::runtime_error("no calibrated DEM tube of a = " + std::to_string(d.aspect));
      StudyRun r{column_name(d) + ", " + std::to_string(cell) + " m", d, *b,
                 terrain::run_column_collapse(dem_column_case(d, cell, true, true), soil),
                 terrain::run_column_collapse(dem_column_case(*b, cell, true, true), sand)};
      std::printf("[ measured ] mu_r %g, %s: r99 %.2f (DEM %.2f; calibrated material %.2f, DEM %.2f), edge %.2f (DEM %.2f; "
                  "%.2f, %.2f), height %.2f (DEM %.2f; %.2f, %.2f)\n",
                  m.rolling_friction, r.name.c_str(), r.model.runout_over_r0, d.runout, r.calibrated_model.runout_over_r0,
                  b->runout, r.model.edge_runout_over_r0, d.edge_runout, r.calibrated_model.edge_runout_over_r0,
                  b->edge_runout, r.model.final_height_over_r0, d.height, r.calibrated_model.final_height_over_r0, b->height);
      std::printf("[ measured ] mu_r %g, %s: over the calibrated material, r99 %.2f (DEM %.2f), height %.2f (DEM %.2f)\n",
                  m.rolling_friction, r.name.c_str(), r.model.runout_over_r0 / r.calibrated_model.runout_over_r0,
                  d.runout / b->runout, r.model.final_height_over_r0 / r.calibrated_model.final_height_over_r0,
                  d.height / b->height);
      out.push_back(r);
    }
  }
  return out;
}

// The rougher material (rolling friction 0.6). The DEM's run-out falls by
// a quarter (r99 -21 / -26 / -24 % at a = 0.5 / 1 / 2) and its heights rise
// (+12 / +15 % at a = 1 / 2); the model's barely move (r99 +4 / +3 % at
// a = 1 / 2 at 10 cm, +2 / +1 % at 5 cm, -3 / -12 % at a = 0.5, heights +1 to
// +5 %): the automaton's stop angle, 3 deg under the repose angle (an
// estimate) and so 5.4 deg steeper, lengthens its run-out (the automaton
// acts on the flow's cells), which outweighs the floor's friction
// (docs/fast_flows.md, "A rougher material, and a smoother one"). Its
// rougher tubes so come within 12 % of the rougher DEM's r99 at a >= 1
// because the DEM came to them: on the calibrated material they are 28-34
// % short. Held: the DEM's response, and the model within 15 % (r99,
// a >= 1) and 16 % (height) of the rougher DEM.
TEST(DemFrictionStudy, ARougherMaterialsColumnsAgainstItsDem) {
  ASSERT_EQ(kFrictionStudy[0].rolling_friction, 0.6);
  const std::vector<StudyRun> runs = study(kFrictionStudy[0]);
  ASSERT_EQ(runs.size(), 6u);
  for (const StudyRun& r : runs) {
    const DemColumn &d = r.dem, &b = r.calibrated_dem;
    EXPECT_TRUE(r.model.books_exact && r.model.flow_at_rest && r.calibrated_model.books_exact) << r.name;
    EXPECT_LT(d.runout, 0.8 * b.runout) << r.name << ": the DEM's rougher grains run out a quarter shorter";
    if (d.aspect >= 1.0) {
      EXPECT_GT(d.height, 1.1 * b.height) << r.name << ": and stand taller";
      EXPECT_NEAR(r.model.runout_over_r0 / d.runout, 1.0, 0.15) << r.name;
    }
    EXPECT_NEAR(r.model.final_height_over_r0 / d.height, 1.0, 0.16) << r.name;
  }
}

// The smoother material (rolling friction 0.15: repose 27.0 deg, thick
// layer 19.8, floor 15.2). The DEM's run-out grows by half (r99 +60 / +65 /
// +51 % at a = 0.5 / 1 / 2) and its heights fall (-18 / -17 % at a = 1 and
// 2); the model's moves far less (r99 +10 / +3 / +0 % at 10 cm, +21 / +8 /
// +9 % at 5 cm), 52-57 % short of the smoother DEM at a >= 1. Across the
// three materials the DEM's r99 at a = 1 spans 0.87-1.93 r0, the model's
// 0.83-0.87 (10 cm): it does not follow the material's friction
// (docs/fast_flows.md, "A rougher material, and a smoother one"). Held: the DEM's response, and
// the model's run-out moving, if at all, the DEM's way.
TEST(DemFrictionStudy, ASmootherMaterialsColumnsAgainstItsDem) {
  ASSERT_EQ(kFrictionStudy[1].rolling_friction, 0.15);
  const std::vector<StudyRun> runs = study(kFrictionStudy[1]);
  ASSERT_EQ(runs.size(), 6u);
  for (const StudyRun& r : runs) {
    const DemColumn &d = r.dem, &b = r.calibrated_dem;
    EXPECT_TRUE(r.model.books_exact && r.model.flow_at_rest && r.calibrated_model.books_exact) << r.name;
    EXPECT_GT(d.runout, 1.4 * b.runout) << r.name << ": the DEM's smoother grains run out half as far again";
    if (d.aspect >= 1.0) {
      EXPECT_LT(d.height, 0.9 * b.height) << r.name << ": and stand lower";
    }
    EXPECT_GT(r.model.runout_over_r0, 0.98 * r.calibrated_model.runout_over_r0) << r.name;
  }
}

}  // namespace
}  // namespace skidsim::report::perf
