// Point pour: the cone's flank settles at the model's repose angle and the
// cone is round (docs/terrain_model.md, "The avalanche rule"; issue evidence).
#include <gtest/gtest.h>

#include "terrain/pile_metrics.h"
#include "tests/test_support.h"

namespace skidsim::terrain {
namespace {

using testing::kDt;

struct PourCase {
  double cell_m;
  double volume_m3;
  double pour_s;
};

class PointPour : public ::testing::TestWithParam<PourCase> {};

TEST_P(PointPour, ConeHasReposeSlopeAndIsRound) {
  const PourCase pc = GetParam();
  const SoilFlowParameters soil;  // dry sand defaults
  // Size the grid for the cone the volume makes at the stop angle, plus room.
  const double radius_m = std::cbrt(3.0 * pc.volume_m3 / (kPi * std::tan(soil.stop_angle_deg * kPi / 180.0)));
  const int n = 2 * static_cast<int>(std::ceil(1.3 * radius_m / pc.cell_m)) + 1;
  GranularGrid g(testing::square_spec(n, pc.cell_m), soil, kDt);
  const int c = n / 2;
  const long pour_steps = std::lround(pc.pour_s / kDt);
  for (long s = 0; s < pour_steps; ++s) {
    g.add_material_m3(c, c, pc.volume_m3 / static_cast<double>(pour_steps));
    g.step();
  }
  ASSERT_GE(testing::settle(g, 200000), 0) << "the pile did not come to rest";

  // The foot of the pile: where 1 cm of material remains (a survey's
  // resolution; the last millimetres of the concave foot run out unevenly).
  const PileMetrics m = measure_pile(g, c, c, 0.01);
  RecordProperty("flank_slope_deg", std::to_string(m.flank_slope_deg));
  RecordProperty("radius_axes_m", std::to_string(m.radius_axes_m));
  RecordProperty("radius_diagonals_m", std::to_string(m.radius_diagonals_m));
  std::printf("cell %.4f m: flank %.2f deg (alpha_I %.1f, alpha %.1f), radius axes %.4f m, diagonals %.4f m, "
              "apex %.3f m, max slope %.2f deg\n",
              pc.cell_m, m.flank_slope_deg, soil.stop_angle_deg, soil.repose_angle_deg, m.radius_axes_m,
              m.radius_diagonals_m, m.apex_material_m, testing::max_slope_deg(g));

  // The poured flank runs as an avalanche and stops at alpha_I (4.5): the
  // expected repose angle of a poured cone is the stop angle. Tolerance 1 deg.
  EXPECT_NEAR(m.flank_slope_deg, soil.stop_angle_deg, 1.0);
  // Round, not a square or diamond pyramid: radii within 3 %.
  EXPECT_NEAR(m.radius_diagonals_m / m.radius_axes_m, 1.0, 0.03);
  // At rest, no slope is steeper than the static repose angle.
  EXPECT_LE(testing::max_slope_deg(g), soil.repose_angle_deg + testing::kRestSlopeToleranceDeg);
  EXPECT_TRUE(g.ledger().balanced());
}

INSTANTIATE_TEST_SUITE_P(CellSizes, PointPour,
                         ::testing::Values(PourCase{0.05, 0.5, 10.0}, PourCase{0.025, 0.5, 10.0}),
                         [](const auto& p) { return "cell_" + std::to_string(static_cast<int>(p.param.cell_m * 1000)) + "mm"; });

}  // namespace
}  // namespace skidsim::terrain
