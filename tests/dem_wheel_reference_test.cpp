// skidsim's wheel against the stored LIGGGHTS wheel runs (dem/wheel/results;
// scripts/dem_reference.sh): the lab wheel on the grid in dem_sand, whose
// Bekker, unloading and Janosi parameters come from the DEM's plate and
// shear-box tests alone (dem/README.md), with as many cells per wheel
// diameter as the loader's tyre has in sessions at 10 and 5 cm
// (report/dem_wheels.h), compared in z / D, DP / W and T / (W r).
//
// The bounds hold what is reached (docs/soil_contact.md, "Wheels against the
// DEM reference": the Wong-Reece theory in the calibrated soil sinks 15-70 %
// deeper than this DEM wheel and pulls harder when driven, and meets its
// towed rolling resistance), so that a change that loses it fails; tighten
// them as the model improves.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "io/soil_table.h"
#include "report/dem_wheels.h"
#include "report/perf_report_parts.h"

namespace skidsim::report::perf {
namespace {


// The soil table's dem_sand holds what the DEM's calibration tests measured
// (one fact, two places: the table is what skidsim reads, the CSVs what the
// DEM wrote), to the table's rounding.
TEST(DemSand, TableHoldsTheCalibratedParameters) {
  const terrain::SoilMechanics soil = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").terramechanics;
  const auto bekker = read_csv_quantities(repository_dem_dir() / "wheel" / "results" / "bekker.csv");
  EXPECT_NEAR(soil.n, bekker.at("n"), 0.001);
  EXPECT_NEAR(soil.k_c_kN_per_m_n1, bekker.at("k_c"), 0.001 * std::abs(bekker.at("k_c")));
  EXPECT_NEAR(soil.k_phi_kN_per_m_n2, bekker.at("k_phi"), 0.001 * bekker.at("k_phi"));
  EXPECT_NEAR(soil.unload_k0_kPa_per_m, bekker.at("unload_k0"), 0.001 * bekker.at("unload_k0"));
  EXPECT_NEAR(soil.unload_Au_kPa_per_m2, bekker.at("unload_Au"), 0.001 * bekker.at("unload_Au"));
  const auto janosi = read_csv_quantities(repository_dem_dir() / "calibration" / "results" / "janosi.csv");
  EXPECT_NEAR(soil.shear_modulus_K_m, janosi.at("all"), 1e-5);
  const auto material = read_csv_quantities(repository_dem_dir() / "calibration" / "material.csv");
  EXPECT_NEAR(soil.friction_angle_deg, material.at("friction_angle_c0_deg"), 0.05);
  EXPECT_NEAR(soil.tool_friction_angle_deg, material.at("tool_friction_angle_deg"), 0.05);
  const terrain::SoilFlowParameters flow = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  EXPECT_NEAR(flow.repose_angle_deg, material.at("repose_angle_deg"), 0.05);
  EXPECT_NEAR(flow.flowing_friction_angle_deg, material.at("flowing_friction_angle_deg"), 0.05);
  EXPECT_NEAR(flow.thin_layer_friction_angle_deg, material.at("thin_layer_friction_angle_deg"), 0.05);
  EXPECT_NEAR(flow.thin_layer_decay_grains, material.at("thin_layer_decay_grains"), 0.005);
  EXPECT_NEAR(flow.bed_start_angle_deg, material.at("bed_start_angle_deg"), 0.05);
  EXPECT_NEAR(flow.impact_sheet_speed_ratio, material.at("impact_sheet_speed_ratio"), 0.005);
  EXPECT_DOUBLE_EQ(flow.grain_diameter_m, material.at("particle_diameter_m"));
  EXPECT_EQ(soil.cohesion_kPa, 0.0);  // the DEM material has no cohesion model
}

class DemWheelCellSizes : public ::testing::TestWithParam<double> {};

TEST_P(DemWheelCellSizes, AgainstTheStoredDemRuns) {
  const io::SoilRecord soil = io::load_soil_table(io::default_soil_table_path()).at("dem_sand");
  const std::vector<DemWheel> runs = read_dem_wheels(repository_dem_dir() / "wheel" / "results");
  ASSERT_EQ(runs.size(), 6u);
  for (const DemWheel& dem : runs) {
    const WheelLike s = wheel_like(dem, soil.terramechanics, soil.flow, GetParam());
    const WheelReference ref = closed_form_like(dem, soil.terramechanics);
    const double D = 2.0 * dem.radius_m, W = dem.load_N, Wr = dem.load_N * dem.radius_m;
    std::printf("[ measured ] %s %+.3f, %.1f cells/D: z/D %.4f (DEM %.4f, closed form %.4f), DP/W %+.3f (DEM %+.3f, %+.3f), "
                "T/Wr %+.3f (DEM %+.3f, %+.3f)\n",
                dem.towed ? "towed" : "slip ", dem.slip, GetParam(), s.run.sinkage_m / D, dem.sinkage_m / D,
                ref.sinkage_m / D, s.run.drawbar_pull_N / W, dem.drawbar_pull_N / W, ref.drawbar_pull_N / W,
                s.run.drive_torque_Nm / Wr, dem.torque_Nm / Wr, ref.torque_Nm / Wr);
    // skidsim is the Wong-Reece wheel on the grid: within 1 % of its closed
    // form in sinkage, and of W (W r) in pull and torque, at both cell sizes.
    EXPECT_NEAR(s.run.sinkage_m, ref.sinkage_m, 0.01 * ref.sinkage_m);
    EXPECT_NEAR(s.run.drawbar_pull_N, ref.drawbar_pull_N, 0.01 * W);
    EXPECT_NEAR(s.run.drive_torque_Nm, ref.torque_Nm, 0.01 * Wr);
    // Against the DEM, what is reached (not the 20 %): the theory
    // sinks deeper than the DEM wheel, by 1.15-1.70 times (more with slip:
    // Lyasko's slip sinkage outgrows the DEM's past s = 0.2), ...
    const double z_ratio = s.run.sinkage_m / dem.sinkage_m;
    EXPECT_GT(z_ratio, 1.0);
    EXPECT_LT(z_ratio, 1.8);
    if (dem.towed) {
      // ... meets the towed wheel's rolling resistance within 0.02 W
      // (0.175 against 0.156 W) ...
      EXPECT_NEAR(s.run.drawbar_pull_N, dem.drawbar_pull_N, 0.05 * W);
    } else if (dem.slip > 0.0) {
      // ... and pulls and turns harder when driven: the pull by 0.10-0.13 W
      // over the DEM's, the torque 1.26-1.60 times the DEM's ...
      EXPECT_GT(s.run.drawbar_pull_N, dem.drawbar_pull_N);
      EXPECT_LT(s.run.drawbar_pull_N - dem.drawbar_pull_N, 0.15 * W);
      EXPECT_GT(s.run.drive_torque_Nm / dem.torque_Nm, 1.0);
      EXPECT_LT(s.run.drive_torque_Nm / dem.torque_Nm, 1.8);
    } else {
      // ... while a braked wheel's torque in the DEM is a fifth of the
      // theory's and its resistance half: both the same sign, the theory's
      // larger.
      EXPECT_LT(s.run.drawbar_pull_N, dem.drawbar_pull_N);
      EXPECT_LT(s.run.drive_torque_Nm, dem.torque_Nm);
      EXPECT_LT(dem.torque_Nm, 0.0);
    }
  }
}

// The DEM's own trends, which skidsim shares: the wheel sinks deeper and
// pulls harder with slip up to 0.2, and the sinkage keeps growing with slip
// (z(s) / z(towed) 1.19, 1.33, 1.63, 1.90 at 0.1, 0.2, 0.4, 0.6; Lyasko's
// factor 1.16, 1.33, 1.75, 2.29).
TEST(DemWheel, SinksDeeperAndPullsHarderWithSlip) {
  const std::vector<DemWheel> runs = read_dem_wheels(repository_dem_dir() / "wheel" / "results");
  ASSERT_EQ(runs.size(), 6u);
  for (size_t k = 2; k < runs.size(); ++k) EXPECT_GT(runs[k].sinkage_m, runs[k - 1].sinkage_m) << "slip " << runs[k].slip;
  EXPECT_TRUE(runs[1].towed);
  EXPECT_GT(runs[2].drawbar_pull_N, runs[1].drawbar_pull_N);
  EXPECT_GT(runs[3].drawbar_pull_N, runs[2].drawbar_pull_N);
  EXPECT_NEAR(runs[1].torque_Nm, 0.0, 0.02 * runs[1].load_N * runs[1].radius_m);  // towed: free to spin
  for (const DemWheel& w : runs) EXPECT_NEAR(w.load_N, runs.front().load_N, 0.02 * w.load_N);  // the servo's load
}

INSTANTIATE_TEST_SUITE_P(SessionCellsPerDiameter, DemWheelCellSizes,
                         ::testing::Values(kSessionCellsPerDiameter10cm, kSessionCellsPerDiameter5cm));

}  // namespace
}  // namespace skidsim::report::perf
