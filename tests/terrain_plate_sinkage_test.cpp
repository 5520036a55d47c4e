// Plate sinkage (docs/validation.md, case 4; thesis 7.3.1, table 7.6): a
// rigid 1 m x 1 m plate loaded with its weight settles at Bekker's depth
// z = (m g / A / (k_c / b + k_phi))^(1/n), for several n, whatever the cell
// size. The plate's edges do not fall on cell edges, so partly covered cells
// must carry their share. Then the imprint it leaves and the reload line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "terrain/body_shapes.h"
#include "terrain/soil_contact.h"
#include "experiments/loading_experiments.h"
#include "tests/soil_contact_support.h"

namespace skidsim::terrain {
namespace {

using testing::TranslatingBody;

constexpr double kDt = 0.002;
constexpr double kSoilDepth = 0.5;
constexpr double kPlateHalfThickness = 0.05;

struct PlateRun {
  double sinkage_m = 0.0;
  double final_speed_m_s = 0.0;
  double supported_N = 0.0;
};

// The plate-loading experiment (experiments/loading_experiments.h) on 0.5 m of sand;
// the soil's damping keeps the loading branch overdamped, so the plate
// creeps down to rest.
PlateRun settle_plate(const SoilMechanics& soil, double mass_kg, double cells_per_m) {
  GranularGrid g = testing::flat_site(cells_per_m, 1.7, kSoilDepth, kDt);
  const PlateLoadingRun r = run_plate_loading(g, soil, mass_kg, kSoilDepth, kDt);
  return {r.sinkage_m, r.final_speed_m_s, r.supported_N};
}

class PlateSinkageExponent : public ::testing::TestWithParam<double> {};

TEST_P(PlateSinkageExponent, SettlesAtBekkerDepthForEveryMassAndCellSize) {
  {
    const double n = GetParam();
    const SoilMechanics soil = plate_test_soil(n);
    for (double mass : {200.0, 500.0, 1000.0}) {
      const double expected = bekker_plate_depth_m(soil, mass);
      double lowest = 1e9, highest = 0.0;
      for (double cells_per_m : {5.0, 10.0, 20.0, 50.0}) {
        const PlateRun run = settle_plate(soil, mass, cells_per_m);
        SCOPED_TRACE(::testing::Message() << "n = " << n << ", m = " << mass << " kg, " << cells_per_m
                                          << " cells/m: sinkage " << run.sinkage_m << " m, Bekker " << expected);
        std::printf("plate n=%.1f m=%4.0f kg %2.0f cells/m: sinkage %.5f m, Bekker %.5f m, error %+.3f %%\n", n, mass,
                    cells_per_m, run.sinkage_m, expected, 100.0 * (run.sinkage_m / expected - 1.0));
        EXPECT_NEAR(run.sinkage_m, expected, 0.02 * expected);
        EXPECT_LT(run.final_speed_m_s, 1e-5);
        EXPECT_NEAR(run.supported_N, mass * kGravity_m_s2, 0.01 * mass * kGravity_m_s2);
        lowest = std::min(lowest, run.sinkage_m);
        highest = std::max(highest, run.sinkage_m);
      }
      // Independent of the cell size (thesis fig. 7.10 b).
      EXPECT_LT((highest - lowest) / expected, 0.02) << "n = " << n << ", m = " << mass;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Exponents, PlateSinkageExponent, ::testing::Values(0.5, 1.1, 1.5, 2.0),
                         [](const ::testing::TestParamInfo<double>& param) {
                           return "n_" + std::to_string(static_cast<int>(std::lround(param.param * 10))) + "_tenths";
                         });

// Wong's dry sand with its real parameters: the plate leaves an imprint as
// deep as the plastic part of its sinkage, and loading it again follows the
// stiff reload line up to the old peak, then the loading curve.
TEST(PlateSinkage, LeavesItsImprintAndReloadsAlongTheReloadLine) {
  SoilMechanics soil;  // dry sand (LLL), n = 1.1
  soil.k_phi_kN_per_m_n2 = 150.0;  // a soft sand: sinkage of centimetres
  // A reload line that gives back a quarter of an 8 cm sinkage, so that the
  // line spans many samples.
  soil.unload_k0_kPa_per_m = 0.0;
  soil.unload_Au_kPa_per_m2 = 6000.0;
  const double cells_per_m = 20.0;
  // Walls of the imprint that stand (a cohesive soil's steep repose angle),
  // so that the pressure read below is the compacted soil's alone.
  SoilFlowParameters flow;
  flow.repose_angle_deg = 65.0;
  flow.stop_angle_deg = 62.0;
  GranularGrid g = testing::flat_site(cells_per_m, 1.7, kSoilDepth, kDt, flow);
  SoilContactModel model(g, soil);
  OrientedBox plate;
  plate.half_extents_m = {0.5, 0.5, kPlateHalfThickness};
  const double x = 0.83, y = 0.79;
  const double modulus = bekker_modulus_Pa(soil, 1.0);
  // Displacement control (a bevameter): press to z1, lift clear, press again
  // to z2 > z1, recording the pressure on the way.
  const auto press_to = [&](double from_m, double to_m, std::map<double, double>* curve) {
    const int steps = 400;
    for (int k = 0; k <= steps; ++k) {
      const double sinkage = from_m + (to_m - from_m) * k / steps;
      plate.centre_m = {x, y, kSoilDepth - sinkage + kPlateHalfThickness};
      BodyMotion still;
      still.reference_point_m = plate.centre_m;
      const BodyReaction r = model.interact(0, plate, still);
      if (curve) (*curve)[sinkage] = r.force_N.z();  // on 1 m^2: pressure in Pa
      g.step();
    }
  };
  const double z1 = 0.08, z2 = 0.12;
  std::map<double, double> first, second;
  press_to(0.0, z1, &first);
  // On the loading curve, p = k z^n.
  for (const auto& [z, p] : first) {
    if (z < 0.01) continue;
    EXPECT_NEAR(p, modulus * std::pow(z, soil.n), 0.02 * modulus * std::pow(z, soil.n)) << "z = " << z;
  }
  press_to(z1, -0.05, nullptr);  // lift clear
  model.release(0);
  for (int k = 0; k < 500; ++k) g.step();  // nothing slumps: the imprint stays

  // The imprint: the middle of the footprint is down by the plastic sinkage.
  const double plastic = plastic_sinkage_m(soil, modulus, z1);
  const int ci = static_cast<int>(std::lround(x * cells_per_m)), cj = static_cast<int>(std::lround(y * cells_per_m));
  EXPECT_NEAR(kSoilDepth - g.surface_m(ci, cj), plastic, 0.01 * z1);
  EXPECT_NEAR(kSoilDepth - g.surface_m(ci + 8, cj - 8), plastic, 0.01 * z1);
  EXPECT_NEAR(g.surface_m(ci + 12, cj), kSoilDepth, 1e-9);  // outside the footprint: untouched
  EXPECT_GT(plastic, 0.5 * z1);

  press_to(0.0, z2, &second);
  const double peak_pressure = modulus * std::pow(z1, soil.n);
  const double k_u = unload_stiffness_Pa_per_m(soil, z1);
  int reload_points = 0, loading_points = 0;
  for (const auto& [z, p] : second) {
    if (z < plastic - 0.001) {
      EXPECT_LT(p, 0.02 * peak_pressure) << "z = " << z << ": no load before the imprint is reached";
    } else if (z > plastic + 0.002 && z < z1 - 0.002) {
      const double reload = peak_pressure - k_u * (z1 - z);
      EXPECT_NEAR(p, reload, 0.03 * peak_pressure) << "z = " << z << ": on the reload line";
      ++reload_points;
    } else if (z > z1 + 0.002) {
      const double loading = modulus * std::pow(z, soil.n);
      EXPECT_NEAR(p, loading, 0.02 * loading) << "z = " << z << ": back on the loading curve";
      ++loading_points;
    }
  }
  EXPECT_GT(reload_points, 10);
  EXPECT_GT(loading_points, 50);
  EXPECT_TRUE(g.ledger().balanced());
}

}  // namespace
}  // namespace skidsim::terrain

namespace skidsim::terrain {
namespace {

// Soil regions: a plate straddling soft and stiff soil is carried by each
// part of its footprint at that soil's pressure.
TEST(SoilRegions, EachPartOfTheFootprintFollowsItsOwnSoil) {
  for (double cells_per_m : {10.0, 20.0}) {
    GranularGrid g = testing::flat_site(cells_per_m, 2.0, kSoilDepth, kDt);
    SoilMechanics soft = plate_test_soil(1.1), stiff = soft;
    stiff.k_phi_kN_per_m_n2 *= 3.0;
    SoilContactModel model(g, soft);
    const int stiff_index = model.add_soil(stiff);
    const int boundary_i = static_cast<int>(std::lround(1.0 * cells_per_m));  // x >= 1 - d/2 is stiff
    for (int j = 0; j < g.ny(); ++j)
      for (int i = boundary_i; i < g.nx(); ++i) model.set_soil_region(i, j, stiff_index);
    const double boundary_x = (boundary_i - 0.5) / cells_per_m;
    OrientedBox plate;
    plate.half_extents_m = {0.5, 0.5, kPlateHalfThickness};
    const double x0 = 0.6137;  // the plate spans x0 .. x0 + 1
    const double z = 0.05;
    BodyReaction r;
    for (int k = 0; k <= 200; ++k) {
      plate.centre_m = {x0 + 0.5, 1.0071, kSoilDepth - z * k / 200.0 + kPlateHalfThickness};
      BodyMotion still;
      still.reference_point_m = plate.centre_m;
      r = model.interact(0, plate, still);
      g.step();
    }
    const double soft_area = boundary_x - x0, stiff_area = 1.0 - soft_area;
    const double expected = (soft_area * bekker_modulus_Pa(soft, 1.0) + stiff_area * bekker_modulus_Pa(stiff, 1.0)) *
                            std::pow(z, soft.n);
    EXPECT_NEAR(r.force_N.z(), expected, 0.01 * expected) << cells_per_m << " cells/m";
    // The stiff side pushes harder: the pressure's centre moves towards it.
    EXPECT_GT(r.shear_point_m.x(), x0 + 0.5 + 0.05);
  }
  EXPECT_THROW(
      {
        GranularGrid g = testing::flat_site(10.0, 1.0, kSoilDepth, kDt);
        SoilContactModel model(g, SoilMechanics{});
        model.set_soil_region(0, 0, 1);
      },
      std::invalid_argument);
}

}  // namespace
}  // namespace skidsim::terrain

namespace skidsim::terrain {
namespace {

// The contact map's own pressure under a cylinder (a body the cell-by-cell
// Bekker model carries; the loader's wheels take the Wong-Reece wheel of
// terrain/wheel_contact.h instead, tests/terrain_soft_wheel_test.cpp).
// Bekker's rigid-wheel depth z0 = [3 W / ((3 - n)(k_c + b k_phi) sqrt(D))]
// ^(2/(2n+1)) carries the load on the front of the contact only, as for a
// towed wheel. A cylinder standing still is carried by both halves of its
// contact and sinks 2^(-2/(2n+1)) of z0 (0.65 for n = 1.1): that is asserted
// within 15 %. Towed, it must sink deeper than standing and not beyond
// z0 + 15 %; measured, it stays 10-24 % short of z0 (the cells' pressure
// also carries it behind the bottom, where the theory's rear is unloaded).
struct WheelRun {
  double sinkage_m = 0.0;
};

WheelRun run_wheel(double cells_per_m, double mass, double speed_m_s) {
  GranularGrid g = testing::flat_site(cells_per_m, speed_m_s > 0.0 ? 4.0 : 1.6, kSoilDepth, kDt);
  return {run_rigid_wheel(g, SoilMechanics{}, mass, 0.3, 0.3, speed_m_s, kSoilDepth, kDt).sinkage_m};
}

TEST(WheelSinkage, StandingWheelFollowsBekkersRigidWheelFormulaOverBothHalves) {
  const SoilMechanics sand;
  const double radius = 0.3, width = 0.3;
  for (double cells_per_m : {20.0, 40.0}) {
    for (double mass : {300.0, 600.0}) {
      const double load = mass * kGravity_m_s2;
      const double bekker = bekker_rigid_wheel_depth_m(sand, load, radius, width);
      const double towed = run_wheel(cells_per_m, mass, 0.25).sinkage_m;
      const double standing = run_wheel(cells_per_m, mass, 0.0).sinkage_m;
      const double both_halves = bekker * std::pow(2.0, -2.0 / (2.0 * sand.n + 1.0));
      std::printf("wheel D=0.6 m b=0.3 m, %3.0f kg, %2.0f cells/m: towed %.4f m vs Bekker %.4f m (%+.1f %%); "
                  "standing %.4f m vs %.4f m (%+.1f %%)\n",
                  mass, cells_per_m, towed, bekker, 100.0 * (towed / bekker - 1.0), standing, both_halves,
                  100.0 * (standing / both_halves - 1.0));
      EXPECT_NEAR(standing, both_halves, 0.15 * both_halves) << mass << " kg, " << cells_per_m << " cells/m";
      EXPECT_GT(towed, 1.1 * standing) << mass << " kg, " << cells_per_m << " cells/m";
      EXPECT_LT(towed, 1.15 * bekker) << mass << " kg, " << cells_per_m << " cells/m";
    }
  }
}

}  // namespace
}  // namespace skidsim::terrain
