// The tyre model alone: Magic Formula shape, combined slip, and the patch
// deflection that keeps it smooth and bounded at standstill.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/loader_support.h"
#include "vehicle/tyre.h"

namespace skidsim::vehicle {
namespace {

const TyreParameters& tyre() { return skidsim::testing::shipped_loader().tyre; }

TEST(Tyre, MagicFormulaIsOddPeaksAtMuFzAndFallsToSliding) {
  const TyreParameters& p = tyre();
  const double Fz = 6000.0;
  double peak = 0.0, peak_slip = 0.0;
  for (double s = 0.0; s <= 1.0; s += 0.001) {
    const double f = magic_formula(p, s, 0.0, Fz).longitudinal_N;
    EXPECT_NEAR(f, -magic_formula(p, -s, 0.0, Fz).longitudinal_N, 1e-9);
    if (f > peak) {
      peak = f;
      peak_slip = s;
    }
  }
  EXPECT_NEAR(peak, p.mu_x * Fz, 1e-3 * Fz);           // D = mu Fz
  EXPECT_GT(peak_slip, 0.05);
  EXPECT_LT(peak_slip, 0.3);
  // Slip stiffness at the origin: B C D (Pacejka 4.E10).
  const double ds = 1e-6;
  EXPECT_NEAR(magic_formula(p, ds, 0.0, Fz).longitudinal_N / ds, p.Bx * p.Cx * p.mu_x * Fz, 1e-3 * p.Bx * p.Cx * p.mu_x * Fz);
  // Locked wheel: sliding friction D sin(C pi/2) < peak (C > 1).
  EXPECT_LT(magic_formula(p, 1.0, 0.0, Fz).longitudinal_N, peak);
}

TEST(Tyre, CombinedSlipWeightsEachForceDownByTheOther) {
  const TyreParameters& p = tyre();
  const double Fz = 6000.0;
  const TyreForce pure_x = magic_formula(p, 0.1, 0.0, Fz), pure_y = magic_formula(p, 0.0, 0.1, Fz);
  const TyreForce both = magic_formula(p, 0.1, 0.1, Fz);
  EXPECT_LT(both.longitudinal_N, pure_x.longitudinal_N);
  EXPECT_LT(both.lateral_N, pure_y.lateral_N);
  EXPECT_GT(both.longitudinal_N, 0.0);
  EXPECT_GT(both.lateral_N, 0.0);
  // Never beyond the friction circle of the larger mu.
  for (double k = -1.0; k <= 1.0; k += 0.05)
    for (double a = -1.0; a <= 1.0; a += 0.05) {
      const TyreForce f = magic_formula(p, k, a, Fz);
      EXPECT_LE(std::hypot(f.longitudinal_N, f.lateral_N), 1.01 * std::max(p.mu_x, p.mu_y) * Fz);
    }
}

TEST(Tyre, StoppedTyreIsASpringAndRollingReachesTheSteadySlip) {
  const TyreParameters& p = tyre();
  TyreKinematics k;
  k.normal_load_N = 6000.0;
  TyreDeflection u;
  // Standing: a 1 mm creep of the patch gives a restoring force, no drift term.
  k.contact_speed_x = 0.001 / 0.002;
  advance_deflection(p, k, 0.002, u);
  k.contact_speed_x = 0.0;
  const TyreForce f = firm_tyre_force(p, u, k);
  EXPECT_LT(f.longitudinal_N, 0.0);
  EXPECT_NEAR(u.x_m, -0.001, 1e-5);  // less a little relaxation during the creep
  TyreDeflection held = u;
  for (int i = 0; i < 5000; ++i) advance_deflection(p, k, 0.002, held);
  EXPECT_EQ(held.x_m, u.x_m);  // at rest the deflection stays: no creep
  // Rolling at 2 m/s with 10 % drive slip: after a few relaxation lengths the
  // deflection stands for the kinematic slip (V_r - V) / V_r.
  k.contact_speed_x = 2.0;
  k.rolling_speed = 2.0 / 0.9;
  TyreDeflection r;
  for (int i = 0; i < 500; ++i) advance_deflection(p, k, 0.002, r);
  EXPECT_NEAR(deflection_slip_ratio(p, r), 0.1, 1e-6);
  // Spinning in place: bounded at slip 1; pushed sideways while stopped:
  // bounded at 45 degrees.
  k.contact_speed_x = 0.0;
  k.rolling_speed = 1.0;
  for (int i = 0; i < 5000; ++i) advance_deflection(p, k, 0.002, r);
  EXPECT_NEAR(deflection_slip_ratio(p, r), 1.0, 1e-6);
  k.rolling_speed = 0.0;
  k.contact_speed_y = 0.5;
  TyreDeflection s;
  for (int i = 0; i < 5000; ++i) advance_deflection(p, k, 0.002, s);
  EXPECT_NEAR(deflection_slip_angle(p, s), -0.25 * skidsim::kPi, 1e-6);
  // Off the ground: no force, the patch springs back.
  k.normal_load_N = 0.0;
  advance_deflection(p, k, 0.002, s);
  EXPECT_EQ(s.y_m, 0.0);
  EXPECT_EQ(firm_tyre_force(p, s, k).lateral_N, 0.0);
}

}  // namespace
}  // namespace skidsim::vehicle
