// Exact conservation, order independence, the floor, edges and containers.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "tests/test_support.h"

namespace skidsim::terrain {
namespace {

using testing::kDt;

// A deterministic stream of pours and removals on a site with open edges.
// Returns the caller's own books: the volume the calls reported added minus
// the volume they reported removed.
double run_mixed_session(GranularGrid& g, long steps) {
  std::uint64_t rng = 12345;
  const auto next = [&rng] {
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return rng >> 33;
  };
  double net_m3 = 0.0;
  for (long s = 0; s < steps; ++s) {
    if (s % 7 == 0) net_m3 += g.add_material_m3(static_cast<int>(next() % g.nx()), static_cast<int>(next() % g.ny()), 2e-4);
    if (s % 11 == 0) net_m3 -= g.remove_material_m3(static_cast<int>(next() % g.nx()), static_cast<int>(next() % g.ny()), 1e-4);
    if (s % 5000 < 50) net_m3 += g.add_material_m3(g.nx() / 2, g.ny() / 2, 5e-3);  // a hopper now and then
    g.step();
  }
  return net_m3;
}

TEST(Conservation, ExactOverHundredThousandStepsWithPoursRemovalsAndOpenEdges) {
  GranularGrid g(testing::square_spec(40, 0.05, EdgeKind::kOpen), SoilFlowParameters{}, kDt);
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) g.set_material_m(i, j, 0.1 + 0.005 * ((i * 7 + j * 3) % 11));
  const auto volume_in_cells = [&g] {
    double v = 0.0;
    for (int j = 0; j < g.ny(); ++j)
      for (int i = 0; i < g.nx(); ++i) v += g.material_m(i, j) * g.cell_size_m() * g.cell_size_m();
    return v;
  };
  const double initial_m3 = volume_in_cells();
  const double net_m3 = run_mixed_session(g, 100000);
  const MaterialLedger l = g.ledger();
  EXPECT_GT(l.off_site_total(), 0) << "the test must exercise the open edges";
  EXPECT_GT(l.removed, 0);
  EXPECT_TRUE(l.balanced());
  // The caller's books against the cells and the off-site counter: what was
  // there plus what was poured minus what was dug out equals what is in the
  // cells plus what left over the edges. Tolerance 1e-12 relative (the sums
  // of doubles here carry round-off; the integer ledger above is exact).
  const double off_site_m3 = static_cast<double>(l.off_site_total()) * g.quantum_volume_m3();
  const double expected = initial_m3 + net_m3;
  EXPECT_LE(std::abs(volume_in_cells() + off_site_m3 - expected) / expected, 1e-12);
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) ASSERT_GE(g.material_quanta(i, j), 0);
}

TEST(OrderIndependence, ShuffledSweepOrderIsBitIdentical) {
  GranularGrid a(testing::square_spec(48, 0.05, EdgeKind::kOpen), SoilFlowParameters{}, kDt);
  GranularGrid b(testing::square_spec(48, 0.05, EdgeKind::kOpen), SoilFlowParameters{}, kDt);
  b.set_sweep_shuffle_seed(0xC0FFEE);
  for (GranularGrid* g : {&a, &b}) {
    for (int j = 10; j < 30; ++j)
      for (int i = 5; i < 25; ++i) g->set_material_m(i, j, 0.6);  // a block that slumps
    run_mixed_session(*g, 3000);
  }
  int differing = 0;
  for (int j = 0; j < 48; ++j)
    for (int i = 0; i < 48; ++i)
      differing += (a.material_quanta(i, j) != b.material_quanta(i, j)) || (a.flowing(i, j) != b.flowing(i, j));
  EXPECT_EQ(differing, 0);
  EXPECT_EQ(a.ledger().off_site, b.ledger().off_site);
  EXPECT_EQ(a.active_cell_count(), b.active_cell_count());
}

TEST(OrderIndependence, DenseAndSparseSweepsAreBitIdentical) {
  std::vector<std::unique_ptr<GranularGrid>> grids;
  for (auto mode : {GranularGrid::SweepMode::kSparse, GranularGrid::SweepMode::kDense, GranularGrid::SweepMode::kAuto}) {
    grids.push_back(std::make_unique<GranularGrid>(testing::square_spec(48, 0.05, EdgeKind::kOpen), SoilFlowParameters{}, kDt));
    grids.back()->set_sweep_mode(mode);
    for (int j = 10; j < 30; ++j)
      for (int i = 5; i < 25; ++i) grids.back()->set_material_m(i, j, 0.6);
    run_mixed_session(*grids.back(), 3000);
  }
  for (std::size_t k = 1; k < grids.size(); ++k) {
    int differing = 0;
    for (int j = 0; j < 48; ++j)
      for (int i = 0; i < 48; ++i)
        differing += (grids[0]->material_quanta(i, j) != grids[k]->material_quanta(i, j)) ||
                     (grids[0]->flowing(i, j) != grids[k]->flowing(i, j));
    EXPECT_EQ(differing, 0) << "mode " << k;
    EXPECT_EQ(grids[0]->ledger().off_site, grids[k]->ledger().off_site);
  }
}

// A 2 m tall column one cell wide: it must collapse without negative
// heights, without oscillation (the highest surface never rises: the sweep
// keeps the discrete maximum principle) and come to rest as a smooth pile.
void collapse_column(double cell_m) {
  const int n = static_cast<int>(std::lround(6.0 / cell_m)) | 1;
  GranularGrid g(testing::square_spec(n, cell_m), SoilFlowParameters{}, kDt);
  const int c = n / 2;
  g.set_material_m(c, c, 2.0);
  double highest = g.surface_m(c, c);
  long steps = 0;
  while (!g.at_rest() && steps < 100000) {
    g.step();
    ++steps;
    double now = 0.0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        ASSERT_GE(g.material_quanta(i, j), 0);
        now = std::max(now, g.surface_m(i, j));
      }
    ASSERT_LE(now, highest + 1e-12) << "surface rose at step " << steps;
    highest = now;
  }
  ASSERT_TRUE(g.at_rest());
  EXPECT_LE(testing::max_slope_deg(g), g.soil().repose_angle_deg + testing::kRestSlopeToleranceDeg);
  // Smooth: along each axis the material never rises moving away from the
  // centre (no checkerboard, no ripples).
  for (int k = 1; c + k < n; ++k) {
    EXPECT_LE(g.material_m(c + k, c), g.material_m(c + k - 1, c) + 1e-9);
    EXPECT_LE(g.material_m(c, c - k), g.material_m(c, c - k + 1) + 1e-9);
  }
  EXPECT_TRUE(g.ledger().balanced());
  std::printf("column collapse at %.3f m cells: %d sub-steps, at rest after %.2f s, apex %.3f m\n", cell_m,
              g.flow_law().substeps, steps * kDt, g.material_m(c, c));
}

TEST(Stability, TallThinColumnCollapsesSmoothly) { collapse_column(0.05); }
TEST(Stability, TallThinColumnCollapsesSmoothlyWithSubSteps) { collapse_column(0.01); }

TEST(Edges, ClosedContainerKeepsEverything) {
  GranularGrid g(testing::square_spec(20, 0.05), SoilFlowParameters{}, kDt);
  for (int s = 0; s < 20000; ++s) {
    g.add_material_m3(3, 4, 2e-4);  // pour far more than a cone would hold
    g.step();
  }
  ASSERT_GE(testing::settle(g, 100000), 0);
  const MaterialLedger l = g.ledger();
  EXPECT_EQ(l.off_site_total(), 0);
  EXPECT_EQ(l.in_cells, l.initial + l.added);
  // The container filled up: material lies against every wall.
  EXPECT_GT(g.material_m(19, 19), 0.0);
  EXPECT_GT(g.material_m(0, 19), 0.0);
  EXPECT_LE(testing::max_slope_deg(g), g.soil().repose_angle_deg + testing::kRestSlopeToleranceDeg);
}

TEST(Edges, OpenEdgeDrainsToTheReposeSlope) {
  GridSpec spec = testing::square_spec(60, 0.05);
  spec.edges[kEdgeXMin] = EdgeKind::kOpen;
  GranularGrid g(spec, SoilFlowParameters{}, kDt);
  for (int j = 0; j < 60; ++j)
    for (int i = 0; i < 60; ++i) g.set_material_m(i, j, 0.4);
  ASSERT_GE(testing::settle(g, 200000), 0);
  const MaterialLedger l = g.ledger();
  EXPECT_GT(l.off_site[kEdgeXMin], 0);
  EXPECT_EQ(l.off_site[kEdgeXMax] + l.off_site[kEdgeYMin] + l.off_site[kEdgeYMax], 0);
  EXPECT_TRUE(l.balanced());
  // Far from the drop-off the layer is untouched; at the drop-off it has
  // slumped to a slope no steeper than the repose angle.
  EXPECT_EQ(g.material_quanta(59, 30), std::llround(0.4 / kHeightQuantumM));
  EXPECT_LT(g.material_m(0, 30), 0.1);
  EXPECT_LE(testing::max_slope_deg(g), g.soil().repose_angle_deg + testing::kRestSlopeToleranceDeg);
}

TEST(Base, PileOnAGentleSlopeCreepsDownhillOnly) {
  // Base tilted 15 degrees down towards -x: a pile poured on it stands (the
  // slope is below the repose angle) but spreads further downhill.
  const int n = 81;
  GranularGrid g(testing::square_spec(n, 0.05), SoilFlowParameters{}, kDt);
  const double tilt = std::tan(15.0 * kPi / 180.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) g.set_base_m(i, j, i * 0.05 * tilt);
  const int c = n / 2;
  for (int s = 0; s < 3000; ++s) {
    g.add_material_m3(c, c, 5e-5);
    g.step();
  }
  ASSERT_GE(testing::settle(g, 200000), 0);
  int up = 0, down = 0;
  while (g.material_m(c + up + 1, c) > 1e-3) ++up;
  while (g.material_m(c - down - 1, c) > 1e-3) ++down;
  EXPECT_GT(down, up) << "the pile must reach further downhill";
  EXPECT_LE(testing::max_slope_deg(g), g.soil().repose_angle_deg + testing::kRestSlopeToleranceDeg);
  EXPECT_TRUE(g.ledger().balanced());
}

TEST(Base, MaterialOnASteepBaseSlidesToTheFoot) {
  // Base at 45 degrees, steeper than repose: a layer slides down to the wall
  // at the bottom and piles there; nothing is left clinging high up.
  const int n = 40;
  GranularGrid g(testing::square_spec(n, 0.05), SoilFlowParameters{}, kDt);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      g.set_base_m(i, j, i * 0.05);
      g.set_material_m(i, j, 0.05);
    }
  ASSERT_GE(testing::settle(g, 200000), 0);
  double top_half = 0, bottom_half = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) (i < n / 2 ? bottom_half : top_half) += g.material_m(i, j);
  EXPECT_LT(top_half, 0.05 * bottom_half);
  EXPECT_LE(testing::max_slope_deg(g), g.soil().repose_angle_deg + testing::kRestSlopeToleranceDeg);
  EXPECT_TRUE(g.ledger().balanced());
}

TEST(ActiveSet, TerrainAtRestCostsNothingAndALocalChangeWakesOnlyItsNeighbourhood) {
  GranularGrid g(testing::square_spec(256, 0.05), SoilFlowParameters{}, kDt);
  for (int j = 0; j < 256; ++j)
    for (int i = 0; i < 256; ++i) g.set_material_m(i, j, 0.3);
  ASSERT_GE(testing::settle(g, 1000), 0);
  g.step();
  EXPECT_EQ(g.last_step().cells_checked, 0);
  EXPECT_EQ(g.active_cell_count(), 0u);
  g.add_material_m3(100, 100, 1e-7);  // too little to topple anything
  EXPECT_EQ(g.active_cell_count(), 9u);  // the cell's 3 x 3 neighbourhood
  g.step();
  EXPECT_EQ(g.last_step().cells_checked, 9);
  EXPECT_TRUE(g.at_rest());
}

// A held cell (GranularGrid::set_held: the fast flow owning it) sends
// nothing out and keeps what arrives from its neighbours; released, it
// relaxes as any other. Dense and sparse sweeps alike, the books exact.
TEST(HeldCells, AHeldCellSendsNothingUntilReleased) {
  std::vector<std::int64_t> finals;
  for (auto mode : {GranularGrid::SweepMode::kSparse, GranularGrid::SweepMode::kDense}) {
    GranularGrid g(testing::square_spec(21, 0.1), SoilFlowParameters{}, kDt);
    g.set_sweep_mode(mode);
    g.set_material_m(10, 10, 1.0);  // a column, held
    g.set_material_m(10, 11, 1.5);  // beside a taller one, free
    const int held = g.index(10, 10);
    g.set_held(held, true);
    const std::int64_t before = g.material_quanta(10, 10);
    for (int s = 0; s < 2000; ++s) {
      g.step();
      ASSERT_GE(g.material_quanta(10, 10), before) << "step " << s;
    }
    EXPECT_GT(g.material_quanta(10, 10), before);  // its neighbour's avalanche arrived
    EXPECT_TRUE(g.held(held));
    g.set_held(held, false);
    EXPECT_FALSE(g.held(held));
    ASSERT_GE(testing::settle(g, 100000), 0);
    EXPECT_LT(g.material_quanta(10, 10), before);
    EXPECT_LE(testing::max_slope_deg(g), g.soil().repose_angle_deg + testing::kRestSlopeToleranceDeg);
    EXPECT_TRUE(g.ledger().balanced());
    finals.push_back(g.material_quanta(10, 10));
  }
  EXPECT_EQ(finals[0], finals[1]);
}

}  // namespace
}  // namespace skidsim::terrain
