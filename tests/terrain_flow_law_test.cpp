// The flow coefficient of (4.11), the sweep's stability bound, and the
// validation of soil parameters.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "terrain/flow_law.h"

namespace skidsim::terrain {
namespace {

TEST(FlowLaw, ZPlusFollowsBcreConsistencyRelation) {
  SoilFlowParameters soil;
  soil.rolling_speed_m_per_s = 0.5;
  soil.rolling_layer_m = 0.2;
  soil.min_flow_layer_m = 0.005;
  const FlowLaw law = derive_flow_law(soil, 0.05, 0.002, 64);
  // z+ = dt v h_r / d (4.11): 0.002 * 0.5 * 0.2 / 0.05 = 0.004 m, well within
  // the bound 0.25 * d = 0.0125 m, so one sweep per step.
  EXPECT_EQ(law.substeps, 1);
  EXPECT_DOUBLE_EQ(law.z_plus_per_sweep_m, 0.004);
  EXPECT_DOUBLE_EQ(law.sweep_dt_s, 0.002);
}

TEST(FlowLaw, SmallCellsSubStepToKeepTheBound) {
  SoilFlowParameters soil;
  for (double d : {0.05, 0.02, 0.01, 0.005, 0.0025}) {
    const FlowLaw law = derive_flow_law(soil, d, 0.002, 1000);
    EXPECT_LE(law.z_plus_per_sweep_m / d, kMaxZPlusOverCell + 1e-12) << "cell " << d;
    // Fewest sub-steps that keep the bound: one fewer would break it.
    if (law.substeps > 1) {
      EXPECT_GT(law.z_plus_per_sweep_m * law.substeps / (law.substeps - 1) / d, kMaxZPlusOverCell);
    }
    EXPECT_NEAR(law.sweep_dt_s * law.substeps, 0.002, 1e-15);
  }
  // dt v h_r / d^2 = 0.002 * 1.0 * 0.3 / 0.0025^2 = 96, over the bound 0.25:
  EXPECT_EQ(derive_flow_law(soil, 0.0025, 0.002, 1000).substeps, 384);
}

TEST(FlowLaw, UnstableParametersAreRefusedWithAClearMessage) {
  SoilFlowParameters soil;
  try {
    derive_flow_law(soil, 0.002, 0.002, 8);
    FAIL() << "expected a refusal";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("unstable"), std::string::npos) << msg;
    EXPECT_NE(msg.find("sub-steps"), std::string::npos) << msg;
    EXPECT_NE(msg.find("dry_sand"), std::string::npos) << msg;
  }
}

TEST(FlowLaw, AHugeStabilityRatioIsRefusedNotWrapped) {
  SoilFlowParameters soil;
  // dt v h_r / d^2 ~ 6e8: more sub-steps than an int holds.
  EXPECT_THROW(derive_flow_law(soil, 1e-6, 0.002, 64), std::invalid_argument);
  soil.rolling_speed_m_per_s = 1e10;
  EXPECT_THROW(derive_flow_law(soil, 0.05, 0.002, 1 << 30), std::invalid_argument);
}

TEST(FlowLaw, MovedHeightIsTransportNearTheStopAngleAndDiffusiveAbove) {
  const SoilFlowParameters soil;
  const FlowLaw law = derive_flow_law(soil, 0.05, 0.002, 64);
  // Nothing at or below alpha_I.
  EXPECT_EQ(law.moved_height_m(law.tan_stop), 0.0);
  EXPECT_EQ(law.moved_height_m(law.tan_stop - 0.1), 0.0);
  // Just above alpha_I a layer h_stop moves at v: z+ h_stop / h_r, a finite
  // amount (4.5: an avalanche starts with a strictly positive flow).
  const double transport = law.z_plus_per_sweep_m * soil.min_flow_layer_m / soil.rolling_layer_m;
  EXPECT_DOUBLE_EQ(law.moved_height_m(law.tan_stop + 1e-9), transport);
  // Diffusive above the switch: z+ times the excess slope (4.16), continuous
  // and increasing.
  EXPECT_DOUBLE_EQ(law.moved_height_m(2.0), law.z_plus_per_sweep_m * (2.0 - law.tan_stop));
  double prev = transport;
  for (double t = law.tan_stop + 1e-6; t < 3.0; t += 1e-3) {
    const double m = law.moved_height_m(t);
    EXPECT_GE(m, prev);
    EXPECT_LE(m - prev, law.z_plus_per_sweep_m * 1.0001e-3);
    prev = m;
    // The stability bound rests on this: never more than z+ tan(beta).
    EXPECT_LE(m, law.z_plus_per_sweep_m * t);
  }
}

TEST(FlowLaw, BadSoilValuesNameTheField) {
  const auto expect_field = [](SoilFlowParameters soil, const std::string& field) {
    try {
      validate(soil);
      FAIL() << "expected rejection of " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  SoilFlowParameters s;
  s.bulk_density_kg_m3 = -1;
  expect_field(s, "bulk_density_kg_m3");
  s = {};
  s.stop_angle_deg = 40;  // above alpha
  expect_field(s, "stop_angle_deg");
  s = {};
  s.rolling_layer_m = 0;
  expect_field(s, "rolling_layer_m");
  s = {};
  s.min_flow_layer_m = 1.0;
  expect_field(s, "min_flow_layer_m");
}

}  // namespace
}  // namespace skidsim::terrain
