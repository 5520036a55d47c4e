// Randomised check of the sweep's equivalences on many small sites: sparse,
// dense, automatic and shuffled sweeps must agree bit for bit after every
// step, on flat, tilted and rough bases, with open and closed edges, pours,
// removals, base changes, covered cells, compaction and pushed material; the
// ledger must balance and no cell go negative.
// (The dense sweep examines every cell, so agreement also checks that a cell
// left out of the active set really has nothing to do.)
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <algorithm>
#include <vector>

#include "tests/test_support.h"

namespace skidsim::terrain {
namespace {

class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 1) {}
  std::uint64_t next() {
    state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
    return state_ >> 33;
  }
  int integer(int lo, int hi) { return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi - lo + 1)); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * static_cast<double>(next() % 1000000) / 1e6; }

 private:
  std::uint64_t state_;
};

TEST(SweepEquivalence, SparseDenseAutoAndShuffledAgreeOnRandomSites) {
  int trials_with_flow = 0, trials_with_recorded_flow_x = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Random rng(static_cast<std::uint64_t>(trial) + 1);
    GridSpec spec;
    spec.nx = rng.integer(1, 24);
    spec.ny = rng.integer(1, 24);
    spec.cell_size_m = std::vector<double>{0.2, 0.1, 0.05, 0.025}[static_cast<std::size_t>(rng.integer(0, 3))];
    for (auto& e : spec.edges) e = rng.integer(0, 1) ? EdgeKind::kOpen : EdgeKind::kClosed;
    SoilFlowParameters soil;
    if (rng.integer(0, 1)) soil.stop_angle_deg = soil.repose_angle_deg;  // with and without inertia
    std::vector<std::unique_ptr<GranularGrid>> g;
    for (auto mode : {GranularGrid::SweepMode::kSparse, GranularGrid::SweepMode::kDense, GranularGrid::SweepMode::kAuto,
                      GranularGrid::SweepMode::kSparse}) {
      g.push_back(std::make_unique<GranularGrid>(spec, soil, testing::kDt, 1000));
      g.back()->set_sweep_mode(mode);
    }
    g[3]->set_sweep_shuffle_seed(static_cast<std::uint64_t>(trial) + 99);
    // The flow record (for rendering) is kept by the sparse and the dense
    // grid: it must not change their state, and both must record the same.
    g[0]->record_flow(true);
    g[1]->record_flow(true);
    const int base_kind = rng.integer(0, 2);
    const double tilt = rng.uniform(-1.5, 1.5);
    for (int j = 0; j < spec.ny; ++j)
      for (int i = 0; i < spec.nx; ++i) {
        const double base = base_kind == 0 ? 0.0 : base_kind == 1 ? tilt * i * spec.cell_size_m : rng.uniform(0, 0.3);
        const double material = rng.integer(0, 3) == 0 ? rng.uniform(0, 1.0) : rng.uniform(0, 0.05);
        for (auto& x : g) {
          x->set_base_m(i, j, base);
          x->set_material_m(i, j, material);
        }
      }
    const int steps = rng.integer(50, 300);
    for (int s = 0; s < steps; ++s) {
      const int action = rng.integer(0, 9);
      const int i = rng.integer(0, spec.nx - 1), j = rng.integer(0, spec.ny - 1);
      const double amount = rng.uniform(0, 0.01);
      for (auto& x : g) {
        if (action == 0) x->add_material_m3(i, j, amount);
        if (action == 1) x->remove_material_m3(i, j, amount);
        if (action == 2) x->set_base_m(i, j, amount * 50 - 0.25);
        // What bodies do to the grid: cover cells (no flux across their
        // faces), compact material, push it to a neighbour.
        if (action == 3) x->set_covered(x->index(i, j), !x->covered(x->index(i, j)));
        if (action == 4) x->compact_quanta(x->index(i, j), static_cast<std::int64_t>(amount * 1e9));
        if (action == 5) x->transfer_quanta(x->index(i, j), x->index(spec.nx - 1 - i, j), static_cast<std::int64_t>(amount * 1e9));
        x->step();
      }
      for (std::size_t k = 1; k < g.size(); ++k) {
        for (int jj = 0; jj < spec.ny; ++jj)
          for (int ii = 0; ii < spec.nx; ++ii) {
            ASSERT_EQ(g[0]->material_quanta(ii, jj), g[k]->material_quanta(ii, jj))
                << "trial " << trial << " step " << s << " grid " << k << " cell " << ii << "," << jj;
            ASSERT_EQ(g[0]->flowing(ii, jj), g[k]->flowing(ii, jj)) << "trial " << trial << " step " << s;
            ASSERT_GE(g[k]->material_quanta(ii, jj), 0);
          }
        ASSERT_EQ(g[0]->ledger().off_site, g[k]->ledger().off_site) << "trial " << trial;
        if (k == 1) {
          ASSERT_EQ(g[0]->flow_record_x(), g[1]->flow_record_x()) << "trial " << trial << " step " << s;
          ASSERT_EQ(g[0]->flow_record_y(), g[1]->flow_record_y()) << "trial " << trial << " step " << s;
        }
        ASSERT_TRUE(g[k]->ledger().balanced());
      }
    }
    trials_with_flow += g[0]->ledger().off_site_total() > 0 || !g[0]->at_rest();
    for (const std::int64_t f : g[0]->flow_record_x()) trials_with_recorded_flow_x += f != 0;
  }
  EXPECT_GT(trials_with_flow, 50) << "the random sites must exercise flows and open edges";
  EXPECT_GT(trials_with_recorded_flow_x, 100) << "cells with recorded flow";
}

// A slope steeper than repose falling towards +x: the flow record points
// down it (+x), with no net sideways flow.
TEST(FlowRecord, PointsDownTheSlope) {
  GridSpec spec = testing::square_spec(20, 0.05);
  spec.ny = 6;
  GranularGrid g(spec, SoilFlowParameters{}, testing::kDt);
  g.record_flow(true);
  for (int j = 0; j < spec.ny; ++j)
    for (int i = 0; i < spec.nx; ++i) g.set_material_m(i, j, std::max(0.0, 0.8 - 0.06 * i));
  for (int s = 0; s < 300; ++s) g.step();
  double along = 0.0, across = 0.0;
  for (std::size_t c = 0; c < g.flow_record_x().size(); ++c) {
    along += static_cast<double>(g.flow_record_x()[c]);
    across += static_cast<double>(g.flow_record_y()[c]);
  }
  EXPECT_GT(along, 1e6);
  EXPECT_LT(std::abs(across), 1e-3 * along);
}

TEST(Limits, AmountsBeyondTheGridsRangeAreRefused) {
  GranularGrid g(testing::square_spec(4, 0.05), SoilFlowParameters{}, testing::kDt);
  EXPECT_THROW(g.set_material_m(1, 1, 1e10), std::invalid_argument);
  EXPECT_THROW(g.set_material_m(1, 1, -0.1), std::invalid_argument);
  EXPECT_THROW(g.add_material_m3(1, 1, 1e30), std::invalid_argument);
  EXPECT_THROW(g.add_material_m3(1, 1, std::nan("")), std::invalid_argument);
  EXPECT_THROW(g.set_base_m(1, 1, 1e39), std::invalid_argument);
  EXPECT_THROW(g.set_material_m(4, 0, 0.1), std::invalid_argument);
  g.set_material_m(1, 1, 0.5);
  EXPECT_NEAR(g.remove_material_m3(1, 1, 1e30), 0.5 * 0.05 * 0.05, 1e-12);  // limited to what it holds
  EXPECT_EQ(g.material_quanta(1, 1), 0);
  EXPECT_TRUE(g.ledger().balanced());
  g.step();
}

}  // namespace
}  // namespace skidsim::terrain
