// The friction side study (scripts/dem_reference.sh, stage friction;
// dem/collapse/results_mu_r0.6): the DEM's grains with their rolling
// friction doubled, calibrated on the pile, the inclined layers and the
// erodible bed alone, and their tubes of aspect ratio 0.5, 1 and 2. The
// model takes that calibration (calibrated_flow) and nothing from the
// tubes: does its run-out follow the material's friction as the DEM's does?
// docs/fast_flows.md, "A rougher material".
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "io/soil_table.h"
#include "report/dem_columns.h"

namespace skidsim::report::perf {
namespace {

namespace fs = std::filesystem;

fs::path dem_dir() { return fs::path(io::default_assets_dir()).parent_path() / "dem"; }

// dem_sand's flow law is its calibration's: the soil table and
// calibration/material.csv hold the same angles (within the table's
// rounding), so a second calibration read the same way is the same model.
TEST(DemFrictionStudy, DemSandsFlowLawIsItsCalibrations) {
  const terrain::SoilFlowParameters sand = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  const terrain::SoilFlowParameters read = calibrated_flow(columns_material(dem_dir(), "results"), sand);
  EXPECT_NEAR(read.repose_angle_deg, sand.repose_angle_deg, 0.02);
  EXPECT_NEAR(read.stop_angle_deg, sand.stop_angle_deg, 0.02);
  EXPECT_NEAR(read.flowing_friction_angle_deg, sand.flowing_friction_angle_deg, 0.02);
  EXPECT_NEAR(read.thin_layer_friction_angle_deg, sand.thin_layer_friction_angle_deg, 0.02);
  EXPECT_NEAR(read.thin_layer_decay_grains, sand.thin_layer_decay_grains, 0.002);
  EXPECT_NEAR(read.bed_start_angle_deg, sand.bed_start_angle_deg, 0.02);
  EXPECT_DOUBLE_EQ(read.grain_diameter_m, sand.grain_diameter_m);
  EXPECT_EQ(columns_material(dem_dir(), kRougherGrainsResults), dem_dir() / "collapse" / kRougherGrainsResults / "material.csv");
}

// The rougher material's tubes against its DEM at 10 and 5 cm, beside the
// calibrated material's. The DEM's run-out falls by a quarter (r99 -23 /
// -23 / -24 % at a = 0.5 / 1 / 2) and its heights rise (+13 % at a = 1 and
// 2); the model's barely move (r99 +1 to +4 % at a >= 1, -3 / -14 % at
// a = 0.5, heights +0 to +3 %, at 10 / 5 cm): the automaton's stop angle,
// 3 deg under the repose angle (an estimate) and so 5.4 deg steeper,
// lengthens its run-out (+17-19 % on the calibrated material; the
// automaton acts on the flow's cells), which outweighs the floor's friction
// (-9 / -8 % on the rougher material). Its rougher tubes
// so come within 8 % of the rougher DEM's r99 at a >= 1 because the DEM
// came to them: on the calibrated material they are 21-27 % short
// (docs/fast_flows.md, "A rougher material"). Held: the DEM's response, and
// the model within 15 % (r99, a >= 1) and 16 % (height) of the rougher DEM.
TEST(DemFrictionStudy, ARougherMaterialsColumnsAgainstItsDem) {
  const terrain::SoilFlowParameters sand = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  const terrain::SoilFlowParameters rough = calibrated_flow(columns_material(dem_dir(), kRougherGrainsResults), sand);
  std::printf("[ measured ] the rougher material: repose %.2f, stop %.2f, flowing friction %.2f, thin layers %.2f over "
              "%.2f grains, the bed's start angle %.2f deg\n",
              rough.repose_angle_deg, rough.stop_angle_deg, rough.flowing_friction_angle_deg,
              rough.thin_layer_friction_angle_deg, rough.thin_layer_decay_grains, rough.bed_start_angle_deg);
  const std::vector<DemColumn> base = read_dem_columns(dem_dir()), rougher = read_dem_columns(dem_dir(), kRougherGrainsResults);
  ASSERT_EQ(rougher.size(), 3u);
  for (double cell : {0.1, 0.05}) {
    for (const DemColumn& d : rougher) {
      const DemColumn* b = nullptr;
      for (const DemColumn& c : base)
        if (!c.slot && c.drop_over_r0 == 0.0 && c.aspect == d.aspect) b = &c;
      ASSERT_NE(b, nullptr) << column_name(d);
      const terrain::CollapseRun run = terrain::run_column_collapse(dem_column_case(d, cell, true, true), rough);
      const terrain::CollapseRun was = terrain::run_column_collapse(dem_column_case(*b, cell, true, true), sand);
      const std::string name = column_name(d) + ", " + std::to_string(cell) + " m";
      std::printf("[ measured ] %s: r99 %.2f (DEM %.2f; calibrated material %.2f, DEM %.2f), edge %.2f (DEM %.2f; %.2f, "
                  "%.2f), height %.2f (DEM %.2f; %.2f, %.2f)\n",
                  name.c_str(), run.runout_over_r0, d.runout, was.runout_over_r0, b->runout, run.edge_runout_over_r0,
                  d.edge_runout, was.edge_runout_over_r0, b->edge_runout, run.final_height_over_r0, d.height,
                  was.final_height_over_r0, b->height);
      std::printf("[ measured ] %s: rougher over calibrated, r99 %.2f (DEM %.2f), height %.2f (DEM %.2f)\n", name.c_str(),
                  run.runout_over_r0 / was.runout_over_r0, d.runout / b->runout,
                  run.final_height_over_r0 / was.final_height_over_r0, d.height / b->height);
      EXPECT_TRUE(run.books_exact && run.flow_at_rest && was.books_exact) << name;
      EXPECT_LT(d.runout, 0.8 * b->runout) << name << ": the DEM's rougher grains run out a quarter shorter";
      if (d.aspect >= 1.0) {
        EXPECT_GT(d.height, 1.1 * b->height) << name << ": and stand taller";
        EXPECT_NEAR(run.runout_over_r0 / d.runout, 1.0, 0.15) << name;
      }
      EXPECT_NEAR(run.final_height_over_r0 / d.height, 1.0, 0.16) << name;
    }
  }
}

}  // namespace
}  // namespace skidsim::report::perf
