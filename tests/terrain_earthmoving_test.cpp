// The earthmoving equation (terrain/earthmoving.h) against closed forms
// derived independently of it: Rankine's passive pressure (a smooth vertical
// wall, with and without cohesion) and Coulomb's passive pressure on a rough
// wall, vertical and inclined (Das, "Principles of Geotechnical
// Engineering", Coulomb's passive coefficient with the wall at beta from the
// horizontal on the soil's side and level ground). Coulomb's wedge is the
// McKyes-Ali mechanism without the side crescents, so the minimised force
// must equal it; the crescents only add.
#include "common/physical_constants.h"
#include "terrain/earthmoving.h"

#include <gtest/gtest.h>

#include <cmath>

namespace skidsim::terrain {
namespace {

constexpr double kGamma = 1600.0 * kGravity_m_s2;

CuttingSoil sand(double phi_deg, double delta_deg, double c_kPa = 0.0, double ca_kPa = 0.0) {
  CuttingSoil s;
  s.unit_weight_N_per_m3 = kGamma;
  s.friction_angle_rad = deg_to_rad(phi_deg);
  s.tool_friction_angle_rad = deg_to_rad(delta_deg);
  s.cohesion_Pa = 1000.0 * c_kPa;
  s.tool_adhesion_Pa = 1000.0 * ca_kPa;
  return s;
}

CuttingTool plane_blade(double depth_m, double rake_deg) {
  CuttingTool t;
  t.depth_m = depth_m;
  t.width_m = 1.0;
  t.rake_rad = deg_to_rad(rake_deg);
  t.side_crescents = false;
  return t;
}

// Coulomb's passive coefficient: wall at beta from the horizontal (on the
// soil's side), wall friction delta, level ground.
double coulomb_kp(double phi, double delta, double beta) {
  const double root = std::sqrt(std::sin(phi + delta) * std::sin(phi) / (std::sin(beta + delta) * std::sin(beta)));
  const double s = std::sin(beta - phi);
  return s * s / (std::sin(beta) * std::sin(beta) * std::sin(beta + delta) * (1.0 - root) * (1.0 - root));
}

TEST(Earthmoving, SmoothVerticalWallIsRankine) {
  for (double phi_deg : {20.0, 28.0, 35.0, 42.0})
    for (double d : {0.1, 0.3}) {
      const CuttingForce f = mckyes_ali(sand(phi_deg, 0.0), plane_blade(d, 90.0));
      const double kp = std::pow(std::tan(deg_to_rad(45.0 + 0.5 * phi_deg)), 2);
      EXPECT_NEAR(f.horizontal_N, 0.5 * kGamma * d * d * kp, 1e-6 * f.horizontal_N) << phi_deg;
      EXPECT_NEAR(rad_to_deg(f.failure_angle_rad), 45.0 - 0.5 * phi_deg, 1e-3) << phi_deg;
      EXPECT_NEAR(f.vertical_down_N, 0.0, 1e-9 * f.horizontal_N);
    }
}

TEST(Earthmoving, CohesionOnASmoothVerticalWallIsRankine) {
  for (double phi_deg : {0.0, 15.0, 30.0})
    for (double c_kPa : {5.0, 40.0}) {
      const double d = 0.2;
      const CuttingForce f = mckyes_ali(sand(phi_deg, 0.0, c_kPa), plane_blade(d, 90.0));
      const double kp = std::pow(std::tan(deg_to_rad(45.0 + 0.5 * phi_deg)), 2);
      const double rankine = 0.5 * kGamma * d * d * kp + 2.0 * 1000.0 * c_kPa * d * std::sqrt(kp);
      EXPECT_NEAR(f.horizontal_N, rankine, 1e-6 * rankine) << phi_deg << " deg, " << c_kPa << " kPa";
      EXPECT_NEAR(f.weight_term_N + f.cohesion_term_N, f.horizontal_N, 1e-9 * rankine);
    }
}

TEST(Earthmoving, RoughWallIsCoulombPassive) {
  for (double phi_deg : {25.0, 31.0, 38.0})
    for (double delta_frac : {1.0 / 3.0, 2.0 / 3.0})
      for (double rake_deg : {90.0, 75.0, 60.0, 45.0}) {
        const double phi = deg_to_rad(phi_deg), delta = delta_frac * phi, d = 0.15;
        const CuttingForce f = mckyes_ali(sand(phi_deg, rad_to_deg(delta)), plane_blade(d, rake_deg));
        const double coulomb = 0.5 * kGamma * d * d * coulomb_kp(phi, delta, deg_to_rad(rake_deg));
        EXPECT_NEAR(f.face_force_N, coulomb, 1e-6 * coulomb)
            << "phi " << phi_deg << ", delta " << rad_to_deg(delta) << ", rake " << rake_deg;
        // The face force is at delta to the face's normal.
        EXPECT_NEAR(f.horizontal_N, f.face_force_N * std::sin(deg_to_rad(rake_deg) + delta), 1e-9 * coulomb);
      }
}

TEST(Earthmoving, TheFailureAngleMinimisesTheForce) {
  const CuttingSoil soil = sand(33.0, 22.0, 4.0, 2.0);
  for (double rake_deg : {30.0, 60.0, 90.0, 110.0}) {
    CuttingTool tool = plane_blade(0.2, rake_deg);
    tool.side_crescents = true;
    tool.width_m = 0.5;
    tool.surcharge_Pa = 800.0;
    const CuttingForce best = mckyes_ali(soil, tool);
    ASSERT_GT(best.face_force_N, 0.0) << rake_deg;
    const double top = max_failure_angle_rad(soil, tool.rake_rad);
    double least = HUGE_VAL;
    for (int k = 1; k < 20000; ++k) {
      const CuttingForce f = mckyes_ali_at(soil, tool, top * k / 20000.0);
      if (f.face_force_N > 0.0) least = std::min(least, f.face_force_N);
    }
    EXPECT_NEAR(best.face_force_N, least, 1e-6 * least) << rake_deg;
    EXPECT_NEAR(best.weight_term_N + best.cohesion_term_N + best.surcharge_term_N + best.adhesion_term_N,
                best.horizontal_N, 1e-9 * best.horizontal_N);
  }
}

TEST(Earthmoving, CrescentsAddToANarrowBladeAndVanishForAWideOne) {
  const CuttingSoil soil = sand(31.0, 21.0);
  for (double rake_deg : {60.0, 90.0}) {
    CuttingTool narrow = plane_blade(0.2, rake_deg);
    const double plane = mckyes_ali(soil, narrow).horizontal_N;
    narrow.side_crescents = true;
    narrow.width_m = 0.2;
    const double n3 = mckyes_ali(soil, narrow).horizontal_N / 0.2;
    EXPECT_GT(n3, 1.3 * plane) << "a blade as wide as deep fails a wider zone than its width";
    CuttingTool wide = narrow;
    wide.width_m = 200.0;
    EXPECT_NEAR(mckyes_ali(soil, wide).horizontal_N / 200.0, plane, 0.01 * plane);
  }
}

TEST(Earthmoving, TheFaceIsPulledInBelowNinetyDegreesOfRakePlusFriction) {
  const CuttingSoil soil = sand(31.0, 21.0);
  EXPECT_GT(mckyes_ali(soil, plane_blade(0.2, 45.0)).vertical_down_N, 0.0);
  EXPECT_LT(mckyes_ali(soil, plane_blade(0.2, 90.0)).vertical_down_N, 0.0);
  // A lower rake cuts with less draft (McKyes 1985, fig. 4.9).
  EXPECT_LT(mckyes_ali(soil, plane_blade(0.2, 45.0)).horizontal_N, mckyes_ali(soil, plane_blade(0.2, 90.0)).horizontal_N);
}

TEST(Earthmoving, OutOfTheSoilOrOutOfRange) {
  const CuttingSoil soil = sand(31.0, 21.0);
  EXPECT_EQ(mckyes_ali(soil, plane_blade(0.0, 90.0)).horizontal_N, 0.0);
  CuttingTool t = plane_blade(0.1, 2.0);
  EXPECT_THROW(validate(soil, t), std::invalid_argument);
  t.rake_rad = deg_to_rad(60.0);
  CuttingSoil bad = soil;
  bad.cohesion_Pa = -1.0;
  EXPECT_THROW(validate(bad, t), std::invalid_argument);
  EXPECT_NO_THROW(validate(soil, t));
}

}  // namespace
}  // namespace skidsim::terrain
