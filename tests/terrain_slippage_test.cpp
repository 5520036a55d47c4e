// Li & Moshell's slippage model (terrain/slippage_law.h), the second ground
// model: its slice analysis against Mohr-Coulomb and Culmann, the grid's
// settled shapes for dry sand and a cohesive cut at two cell sizes, exact
// conservation, order independence, and the stability bound (held at the
// bound, broken beyond it, refused when the sub-steps would not suffice).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "experiments/slippage_study.h"
#include "tests/test_support.h"

namespace skidsim::terrain {
namespace {

using testing::kDt;

SoilFlowParameters slippage_soil(double cohesion_Pa, double phi_deg, double density = 1800.0) {
  SoilFlowParameters soil;
  soil.name = "slip";
  soil.model = GroundModel::kSlippage;
  soil.bulk_density_kg_m3 = density;
  soil.slip_cohesion_Pa = cohesion_Pa;
  soil.slip_friction_angle_deg = phi_deg;
  return soil;
}

double deg(double rad) { return rad * 180.0 / kPi; }
double rad(double deg) { return deg * kPi / 180.0; }

TEST(SliceFailure, CohesionlessSliceFailsPastPhiOnAPlaneAtPhi) {
  const SlippageLaw law = derive_slippage_law(slippage_soil(0.0, 33.0), 0.05, kDt, 64);
  const double d = 0.05;
  EXPECT_FALSE(slice_failure(law, d * std::tan(rad(32.9)), d).fails);
  const SliceFailure f = slice_failure(law, d * std::tan(rad(33.1)), d);
  ASSERT_TRUE(f.fails);
  // c = 0: (3.4) gives beta_0 = phi, the infinite-slope failure plane.
  EXPECT_NEAR(deg(f.critical_angle_rad), 33.0, 1e-9);
  EXPECT_NEAR(f.excess_m, d * (std::tan(rad(33.1)) - std::tan(rad(33.0))), 1e-12);
  // (3.7) on a thin wedge: (run excess / 2) sin(beta_0) per unit weight, so
  // the wedge accelerates at g sin(phi) (0.1 % for a 0.1 deg excess).
  EXPECT_NEAR(f.accel_m_s2, kGravity_m_s2 * std::sin(rad(33.0)), 1e-3 * kGravity_m_s2);
}

TEST(SliceFailure, CohesiveCriticalStepTendsToCulmannsVerticalCut) {
  // A stiff sandy loam (c = 9.65 kPa, phi = 35 deg, the soil table's
  // sandy_loam_23): Culmann's critical height 4 c / gamma tan(45 + phi/2).
  const SoilFlowParameters soil = slippage_soil(9650.0, 35.0);
  const double culmann = culmann_critical_height_m(9650.0, 35.0, 1800.0 * kGravity_m_s2);
  EXPECT_NEAR(culmann, 4.0 * 9650.0 / (1800.0 * kGravity_m_s2) * std::tan(rad(62.5)), 1e-12);
  const SlippageLaw law = derive_slippage_law(soil, 0.05, kDt, 64);
  // A run much shorter than the step is a vertical cut: 0.1 % at 1/1000.
  EXPECT_NEAR(critical_step_m(law, culmann * 1e-3), culmann, 2e-3 * culmann);
  // The critical step separates standing from failing slices at every run,
  // and a longer run (a gentler slice) needs a higher step.
  double previous = 0.0;
  for (const double run : {0.0125, 0.025, 0.05, 0.1, 0.2}) {
    const double critical = critical_step_m(law, run);
    EXPECT_FALSE(slice_failure(law, 0.999 * critical, run).fails) << run;
    EXPECT_TRUE(slice_failure(law, 1.001 * critical, run).fails) << run;
    EXPECT_GT(critical, previous);
    previous = critical;
  }
}

// A square column of dry sand (c = 0) released on a bare base collapses
// and settles with every slope at or below phi, conserving material exactly.
class SlippageColumn : public ::testing::TestWithParam<double> {};

TEST_P(SlippageColumn, DrySandColumnSettlesAtPhiAndConserves) {
  const double cell = GetParam();
  const int n = static_cast<int>(std::lround(3.0 / cell));
  GranularGrid g(testing::square_spec(n, cell), slippage_soil(0.0, 33.0, 1600.0), kDt);
  const int half = static_cast<int>(std::lround(0.2 / cell));
  for (int j = n / 2 - half; j < n / 2 + half; ++j)
    for (int i = n / 2 - half; i < n / 2 + half; ++i) g.set_material_m(i, j, 0.8);
  const std::int64_t total = g.total_quanta();
  const long steps = testing::settle(g, 50000);  // the last quanta creep (docs/terrain_model.md)
  ASSERT_GT(steps, 0) << "not at rest after 100 s";
  EXPECT_EQ(g.total_quanta(), total);
  EXPECT_TRUE(g.ledger().balanced());
  // Every face stands at or below phi (a sub-quantum drop may lean past it).
  EXPECT_LE(testing::max_slope_deg(g), 33.0 + testing::kRestSlopeToleranceDeg);
  // The flank stands near phi, not far below: the slide stops as soon as a
  // slice is stable (no stop angle below phi, unlike the automaton).
  EXPECT_NEAR(testing::median_flank_slope_deg(g), 33.0, 2.0);
}

INSTANTIATE_TEST_SUITE_P(TwoCellSizes, SlippageColumn, ::testing::Values(0.05, 0.025));

// A vertical cut in cohesive soil: a bank one cell from bare base. Below the
// slice model's critical step (which is Culmann's height for a vertical
// cut) it stands; above, it fails and settles into slices that all stand.
class SlippageCut : public ::testing::TestWithParam<double> {};

TEST_P(SlippageCut, CohesiveCutStandsBelowTheCriticalHeightAndFailsAbove) {
  const double cell = GetParam();
  const SoilFlowParameters soil = slippage_soil(2000.0, 30.0);
  const int nx = static_cast<int>(std::lround(4.0 / cell)), ny = 4;
  const auto make = [&](double height_m) {
    GridSpec spec = testing::square_spec(nx, cell);
    spec.ny = ny;
    auto g = std::make_unique<GranularGrid>(spec, soil, kDt);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx / 4; ++i) g->set_material_m(i, j, height_m);
    return g;
  };
  const double critical = critical_step_m(make(0.1)->slippage_law(), cell);
  const double culmann = culmann_critical_height_m(2000.0, 30.0, 1800.0 * kGravity_m_s2);
  // The run (one cell) is short beside the cut: a little above Culmann.
  EXPECT_GT(critical, culmann);
  EXPECT_LT(critical, 1.15 * culmann);

  auto standing = make(0.95 * critical);
  const double before = standing->surface_m(nx / 4 - 1, 1);
  EXPECT_EQ(testing::settle(*standing, 10), 1);  // one sweep finds nothing to move
  EXPECT_EQ(standing->surface_m(nx / 4 - 1, 1), before);

  auto failing = make(1.1 * critical);
  const std::int64_t total = failing->total_quanta();
  ASSERT_GT(testing::settle(*failing, 20000), 1);
  EXPECT_LT(failing->surface_m(nx / 4 - 1, 1), 1.1 * critical - 1e-3);  // the cut's top slid
  EXPECT_EQ(failing->total_quanta(), total);
  // Settled: no slice fails anywhere (its drop over one cell below the
  // critical step), so the debris stands steeper than phi, held by c.
  double worst_ratio = 0.0;
  for (int i = 0; i + 1 < nx; ++i)
    worst_ratio = std::max(worst_ratio, (failing->surface_m(i, 1) - failing->surface_m(i + 1, 1)) / critical);
  EXPECT_LE(worst_ratio, 1.0 + 1e-6);
  EXPECT_GT(testing::max_slope_deg(*failing), 30.0 + 5.0);
}

INSTANTIATE_TEST_SUITE_P(TwoCellSizes, SlippageCut, ::testing::Values(0.05, 0.025));

TEST(SlippageGrid, ResultDoesNotDependOnTheSweepOrderAndOpenEdgesBalance) {
  const auto run = [](std::uint64_t seed) {
    GranularGrid g(testing::square_spec(40, 0.05, EdgeKind::kOpen), slippage_soil(500.0, 30.0), kDt);
    g.set_sweep_shuffle_seed(seed);
    for (int j = 5; j < 25; ++j)
      for (int i = 0; i < 15; ++i) g.set_material_m(i, j, 0.6);  // fails at its sides, and off the -x edge
    for (int s = 0; s < 1500; ++s) g.step();
    EXPECT_TRUE(g.ledger().balanced());
    EXPECT_GT(g.ledger().off_site_total(), 0);
    std::vector<std::int64_t> q;
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) q.push_back(g.material_quanta(i, j));
    return q;
  };
  EXPECT_EQ(run(0), run(12345));
}

TEST(SlippageStability, MonotoneUpToTheBoundOscillatesBeyondIt) {
  const SoilFlowParameters sand = slippage_soil(0.0, 30.0, 1600.0);
  // Four faces a cell: clean at the grid's bound, new maxima past it.
  const SlideOvershoot at_bound = slide_overshoot_at(sand, kMaxSlideCourant);
  EXPECT_LE(at_bound.yard_top_rise_m, 1e-9);
  EXPECT_LE(at_bound.strip_variation_rise_m, 1e-6);
  EXPECT_GT(slide_overshoot_at(sand, 2.0 * kMaxSlideCourant).yard_top_rise_m, 0.005);
  // A strip has two faces a cell, so it holds up to Cr = 1 and breaks past it.
  const SlideOvershoot strip_bound = slide_overshoot_at(sand, 1.0);
  EXPECT_LE(strip_bound.strip_variation_rise_m, 1e-6);
  EXPECT_GT(slide_overshoot_at(sand, 4.0).strip_variation_rise_m, 0.05);
}

TEST(SlippageStability, GridSubStepsToTheBoundAndRefusesWhatItCannotReach) {
  const SoilFlowParameters soil = slippage_soil(0.0, 30.0);
  // v dt / d = 1 * 0.002 / 0.0125 = 0.16: one sweep; at 2.5 mm cells 0.8:
  // two sweeps of Cr 0.4.
  EXPECT_EQ(derive_slippage_law(soil, 0.0125, kDt, 64).substeps, 1);
  const SlippageLaw fine = derive_slippage_law(soil, 0.0025, kDt, 64);
  EXPECT_EQ(fine.substeps, 2);
  EXPECT_LE(fine.max_speed_m_s * fine.sweep_dt_s / 0.0025, kMaxSlideCourant);
  GranularGrid g(testing::square_spec(8, 0.0025), soil, kDt);
  EXPECT_EQ(g.flow_law().substeps, 2);
  EXPECT_EQ(g.slippage_law().substeps, 2);
  try {
    GranularGrid refused(testing::square_spec(8, 0.0025), soil, kDt, 1);
    FAIL() << "a grid past the bound was built";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds the bound 0.5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(derive_slippage_law(soil, 0.05, kDt, 64, 1.0, 1.0), std::invalid_argument);  // beyond, not a study
  SoilFlowParameters bad = soil;
  bad.slip_cohesion_Pa = -1.0;
  EXPECT_THROW(derive_slippage_law(bad, 0.05, kDt, 64), std::invalid_argument);
}

TEST(SlippageGrid, AtRestCostsNothingAndStaysBitForBit) {
  // A rough slope of 20-40 deg in cohesive soil (c = 2 kPa): every one-cell
  // slice stands, so the first sweep moves nothing and then nothing is
  // examined, and the surface stays exactly as laid.
  GranularGrid g(testing::square_spec(50, 0.05), slippage_soil(2000.0, 30.0), kDt);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> rise(0.018, 0.042);  // tan 20 .. 40 deg over 5 cm
  std::vector<double> laid;
  for (int j = 0; j < 50; ++j) {
    double h = 0.2;
    for (int i = 0; i < 50; ++i) {
      h += rise(rng);
      g.set_material_m(i, j, h);
      laid.push_back(g.surface_m(i, j));
    }
  }
  EXPECT_GT(testing::max_slope_deg(g), 35.0);
  g.step();
  EXPECT_EQ(g.last_step().moved_quanta, 0);
  EXPECT_TRUE(g.at_rest());
  for (int s = 0; s < 100; ++s) g.step();
  EXPECT_EQ(g.last_step().cells_checked, 0);
  for (int j = 0; j < 50; ++j)
    for (int i = 0; i < 50; ++i) EXPECT_EQ(g.surface_m(i, j), laid[static_cast<std::size_t>(j * 50 + i)]);
  EXPECT_EQ(g.slide_speed_m_s(10, 10), 0.0);
}

// Soil dumped on cohesive ground is loose (remoulded: no cohesion): it
// slides off a bank at phi while the intact bank under it keeps standing.
TEST(SlippageGrid, DumpedSoilSlidesAtPhiOffAnIntactBank) {
  const SoilFlowParameters loam = slippage_soil(1720.0, 29.0, 1750.0);
  GridSpec spec = testing::square_spec(60, 0.05);
  spec.ny = 20;
  GranularGrid g(spec, loam, kDt);
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) g.set_material_m(i, j, 0.5);  // a 0.5 m cut, below its critical step
  ASSERT_LT(0.5, critical_step_m(g.slippage_law(), 0.05));
  for (int j = 8; j < 12; ++j)
    for (int i = 14; i < 20; ++i) g.add_material_m3(i, j, 0.15 * 0.05 * 0.05);  // a load dumped at the edge
  const std::int64_t total = g.total_quanta();
  ASSERT_GT(testing::settle(g, 20000), 1);
  EXPECT_EQ(g.total_quanta(), total);
  double beyond = 0.0;
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 60; ++i) {
      if (i < 20) {
        EXPECT_GE(g.material_m(i, j), 0.5 - 1e-9) << "the intact bank stands: " << i << ", " << j;
      } else {
        beyond += g.material_m(i, j);
      }
      // Loose soil at rest stands at phi at most towards every lower
      // neighbour. (Not the gradient slope: beside the cut, a foot cell's
      // faces along the wall see the wall's height as a tangential slope
      // over sub-micrometre drops, which no quantum can flow down.)
      if (g.loose_material_m(i, j) <= 1e-6) continue;
      const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
      for (int f = 0; f < 4; ++f) {
        if (!g.contains(i + di[f], j + dj[f])) continue;
        EXPECT_LE(g.surface_m(i, j) - g.surface_m(i + di[f], j + dj[f]), 0.05 * std::tan(rad(29.0 + 0.1)))
            << i << ", " << j << " towards " << f << ": loose " << g.loose_material_m(i, j);
      }
    }
  // Of the 0.009 m^3 dumped 0.3 m from the edge, what stood above phi slid
  // over it (the rest stays on the bank at phi).
  EXPECT_GT(beyond * 0.05 * 0.05, 0.3 * 24 * 0.15 * 0.05 * 0.05);

}

}  // namespace
}  // namespace skidsim::terrain
