// The load of a pile on the base under it (thesis 6.5, 7.3.3, fig. 7.13):
// it sums to the pile's weight, follows the pile smoothly and spreads
// beyond the column under each cell.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "common/physical_constants.h"
#include "terrain/load_spreading.h"
#include "test_support.h"

namespace skidsim::terrain {
namespace {

using testing::kDt;

// A pile poured at the centre of a flat closed grid and left to settle.
GranularGrid poured_pile(double cell_m, double volume_m3) {
  const int n = static_cast<int>(std::lround(3.0 / cell_m));
  GranularGrid g(testing::square_spec(n, cell_m), SoilFlowParameters{}, kDt);
  const int c = n / 2;
  const double per_step = 0.0004;  // m^3 per step
  for (double poured = 0.0; poured < volume_m3; poured += per_step) {
    g.add_material_m3(c, c, per_step);
    g.step();
  }
  testing::settle(g, 200000);
  return g;
}

class PileCellSizes : public ::testing::TestWithParam<double> {};

TEST_P(PileCellSizes, PileLoadSumsToItsWeightAndFollowsItSmoothly) {
  const double d = GetParam();
  const GranularGrid g = poured_pile(d, 0.12);
  ASSERT_TRUE(g.at_rest());
  const double weight_N = static_cast<double>(g.total_quanta()) * g.quantum_mass_kg() * kGravity_m_s2;
  std::vector<double> loads;
  LoadSpreadingScratch scratch;
  for (double block_cells : {1.0, 1.5, 2.0}) {
    LoadSpreading spreading;
    spreading.block_height_cells = block_cells;
    base_loads_N(g, spreading, kGravity_m_s2, &loads, &scratch);
    double sum = 0.0;
    for (double l : loads) sum += l;
    EXPECT_NEAR(sum, weight_N, 1e-12 * weight_N) << "the base loads must sum to the weight";
    // Along the pile's axis: the load peaks at the centre, falls off on
    // both sides, and has no kinks larger than the pile's own.
    const int n = g.nx(), c = n / 2;
    const double column_N = g.material_m(c, c) * g.soil().bulk_density_kg_m3 * kGravity_m_s2 * d * d;
    EXPECT_LT(loads[static_cast<std::size_t>(g.index(c, c))], column_N) << "eps > 1/3 moves load sideways";
    double peak = 0.0;
    for (int i = 0; i < n; ++i) peak = std::max(peak, loads[static_cast<std::size_t>(g.index(i, c))]);
    for (int i = 1; i + 1 < n; ++i) {
      const double l0 = loads[static_cast<std::size_t>(g.index(i - 1, c))];
      const double l1 = loads[static_cast<std::size_t>(g.index(i, c))];
      const double l2 = loads[static_cast<std::size_t>(g.index(i + 1, c))];
      EXPECT_LT(std::abs(l0 - 2.0 * l1 + l2), 0.1 * peak) << "kink at " << i;
      if (i + 1 <= c) {
        EXPECT_LE(l0, l1 + 1e-9 * peak) << "rising towards the centre at " << i;
      }
      if (i > c) {
        EXPECT_LE(l2, l1 + 1e-9 * peak) << "falling from the centre at " << i;
      }
    }
    // The flanks carry load passed out from the core: beyond half the
    // pile's radius the base carries more than the columns there weigh.
    int foot = c;
    while (foot < n - 1 && g.material_m(foot + 1, c) > 0.0) ++foot;
    const int half = c + (foot - c) / 2;
    double flank_load = 0.0, flank_columns = 0.0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        if (std::hypot(i - c, j - c) < half - c) continue;
        flank_load += loads[static_cast<std::size_t>(g.index(i, j))];
        flank_columns += g.material_m(i, j) * g.soil().bulk_density_kg_m3 * kGravity_m_s2 * d * d;
      }
    EXPECT_GT(flank_load, flank_columns);
  }
}

// More layers (thinner blocks) spread the load further: the centre carries
// less.
TEST(LoadSpreading, ThinnerBlocksSpreadMore) {
  const GranularGrid g = poured_pile(0.05, 0.12);
  const int c = g.nx() / 2;
  std::vector<double> loads;
  LoadSpreadingScratch scratch;
  double previous = 0.0;
  for (double block_cells : {1.0, 1.5, 2.0}) {
    LoadSpreading s;
    s.block_height_cells = block_cells;
    base_loads_N(g, s, kGravity_m_s2, &loads, &scratch);
    const double centre = loads[static_cast<std::size_t>(g.index(c, c))];
    EXPECT_GT(centre, previous);
    previous = centre;
  }
}

TEST(LoadSpreading, RejectsParametersOutsideTheirRange) {
  LoadSpreading s;
  s.eps = 0.6;
  EXPECT_THROW(validate(s), std::invalid_argument);
  s.eps = 0.4;
  s.block_height_cells = 0.0;
  EXPECT_THROW(validate(s), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(TwoCellSizes, PileCellSizes, ::testing::Values(0.05, 0.025));

}  // namespace
}  // namespace skidsim::terrain
