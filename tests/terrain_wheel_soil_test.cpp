// The Wong-Reece wheel (terrain/wheel_soil.h) against its closed form, the
// published integrals evaluated apart (experiments/wong_reece_closed_form.h);
// its limits (Bekker's rigid-wheel sinkage, the locked and the flattened
// wheel) and the reload line of a second pass.
#include "terrain/wheel_soil.h"
#include "experiments/wong_reece_closed_form.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace skidsim::terrain {
namespace {

// The soils: Wong's LLL sand (SoilMechanics' default) and a stiff cohesive
// soil (n 0.11, Wong's figures for a heavy clay).
SoilMechanics clay() {
  SoilMechanics s;
  s.n = 0.11;
  s.k_c_kN_per_m_n1 = 41.6;
  s.k_phi_kN_per_m_n2 = 2471.0;
  s.cohesion_kPa = 2.07;
  s.friction_angle_deg = 10.0;
  s.shear_modulus_K_m = 0.01;
  return s;
}

const WheelShape kWheel{0.3, 0.3, 0.0};  // D 0.6 m, b 0.3 m: the terrain tests' wheel

TEST(WongReece, MatchesTheReferenceIntegralsOverSinkageAndSlip) {
  for (const SoilMechanics& soil : {SoilMechanics{}, clay()}) {
    for (const double z : {0.01, 0.03, 0.08}) {
      for (const double s : {0.0, 0.1, 0.2, 0.4, 0.6, 0.9}) {
        const WheelSoilForces m = wong_reece(kWheel, soil, z, s);
        const closed_form::WongReeceResult r = closed_form::wong_reece_reference(closed_form::reference_soil_of(soil), 0.3, 0.3, z, s);
        EXPECT_NEAR(m.vertical_N, r.W, 2e-4 * std::abs(r.W)) << "z " << z << " s " << s;
        EXPECT_NEAR(m.drawbar_pull_N, r.DP, 2e-4 * std::abs(r.W)) << "z " << z << " s " << s;
        EXPECT_NEAR(m.drive_torque_Nm, r.T, 2e-4 * std::abs(r.W) * 0.3) << "z " << z << " s " << s;
      }
    }
  }
}

TEST(WongReece, SinkageForALoadMatchesTheReference) {
  const SoilMechanics sand;
  for (const double load : {1000.0, 3000.0, 6000.0}) {
    for (const double s : {0.0, 0.1, 0.2, 0.4, 0.6}) {
      const double model = wong_reece_sinkage_m(kWheel, sand, load, s);
      const double ref = closed_form::wong_reece_reference_sinkage(closed_form::reference_soil_of(sand), 0.3, 0.3, load, s);
      EXPECT_NEAR(model, ref, 1e-3 * ref) << load << " N, s " << s;
    }
  }
}

// Without shear, with the largest stress at the bottom, no rebound and no
// slip sinkage, W is Bekker's rigid-wheel integral, whose small-sinkage
// form is z0 = [3 W / ((3 - n)(k_c + b k_phi) sqrt(D))]^(2/(2n+1)).
TEST(WongReece, ReducesToBekkersRigidWheelWithoutShear) {
  SoilMechanics s;
  s.friction_angle_deg = 1e-9;
  s.cohesion_kPa = 0.0;
  s.wheel_theta_max_c1 = s.wheel_theta_max_c2 = 0.0;
  s.wheel_slip_sinkage = false;
  s.unload_k0_kPa_per_m = 1e12;
  for (const double load : {500.0, 2000.0}) {
    const double z = wong_reece_sinkage_m(kWheel, s, load, 0.0);
    const double k = 1000.0 * (s.k_c_kN_per_m_n1 + 0.3 * s.k_phi_kN_per_m_n2);
    const double z0 = std::pow(3.0 * load / ((3.0 - s.n) * k * std::sqrt(0.6)), 2.0 / (2.0 * s.n + 1.0));
    // The closed form takes sin(theta) ~ theta: a few per cent at z / D ~ 0.05.
    EXPECT_NEAR(z, z0, 0.04 * z0) << load;
  }
}

TEST(WongReece, PullAndTorqueGrowWithSlipAndATowedWheelSlipsALittle) {
  const SoilMechanics sand;
  const double load = 3000.0;
  double last_dp = -1e9, last_t = -1e9;
  for (double s = -0.5; s <= 0.9 + 1e-9; s += 0.1) {
    const double z = wong_reece_sinkage_m(kWheel, sand, load, s);
    const WheelSoilForces f = wong_reece(kWheel, sand, z, s);
    // The pull levels off past s ~ 0.6 (the slip sinkage's compaction
    // resistance grows as fast as the traction).
    if (s < 0.65) {
      EXPECT_GT(f.drawbar_pull_N, last_dp) << s;
    }
    EXPECT_GT(f.drive_torque_Nm, last_t) << s;
    last_dp = f.drawbar_pull_N;
    last_t = f.drive_torque_Nm;
    std::printf("s %+.1f: z %.4f m, DP %+8.1f N, T %+8.1f N m, theta1 %.1f deg, theta2 %.1f deg\n", s, z,
                f.drawbar_pull_N, f.drive_torque_Nm, rad_to_deg(f.entry_rad), rad_to_deg(f.exit_rad));
  }
  // Towed (no torque): a small positive slip; braked: pull and torque reverse.
  const WheelSoilForces towed = wong_reece(kWheel, sand, wong_reece_sinkage_m(kWheel, sand, load, 0.0), 0.0);
  EXPECT_LT(towed.drawbar_pull_N, 0.0);  // rolling resistance at zero slip
  const WheelSoilForces braked = wong_reece(kWheel, sand, wong_reece_sinkage_m(kWheel, sand, load, -0.5), -0.5);
  EXPECT_LT(braked.drive_torque_Nm, 0.0);
  EXPECT_LT(braked.drawbar_pull_N, 0.0);
}

// A locked wheel slides: the soil is sheared by the distance it slides, so
// the pull stays within the soil's strength, (c A + W tan(phi)).
TEST(WongReece, ALockedWheelResistsWithAtMostTheSoilsStrength) {
  const SoilMechanics sand;
  const double z = wong_reece_sinkage_m(kWheel, sand, 3000.0, -1.0);
  const WheelSoilForces f = wong_reece(kWheel, sand, z, -1.0);
  EXPECT_TRUE(std::isfinite(f.drawbar_pull_N));
  EXPECT_LT(f.drawbar_pull_N, 0.0);
  EXPECT_LT(std::abs(f.drawbar_pull_N), f.shear_strength_N + 0.5 * f.vertical_N);  // plus compaction resistance
}

// A smooth rim (WheelShape::rim_friction_angle_rad) slides on the soil
// before the soil shears where its friction is the lower: the model meets
// the closed form with the interface's friction; a rim gripping at least as
// well as the soil's own friction changes nothing; and a smooth rim pulls
// less than a lugged one at every slip.
TEST(WongReece, ASmoothRimShearsAtTheInterfacesFriction) {
  const SoilMechanics sand;  // phi 28 deg
  closed_form::WongReeceSoil ref = closed_form::reference_soil_of(sand);
  WheelShape smooth = kWheel;
  smooth.rim_friction_angle_rad = deg_to_rad(20.0);
  ref.rim_delta_rad = smooth.rim_friction_angle_rad;
  WheelShape grippy = kWheel;
  grippy.rim_friction_angle_rad = deg_to_rad(35.0);
  for (const double z : {0.02, 0.06}) {
    for (const double s : {-0.3, 0.1, 0.4}) {
      const WheelSoilForces m = wong_reece(smooth, sand, z, s);
      const closed_form::WongReeceResult r = closed_form::wong_reece_reference(ref, 0.3, 0.3, z, s);
      EXPECT_NEAR(m.drawbar_pull_N, r.DP, 2e-4 * std::abs(r.W)) << "z " << z << " s " << s;
      EXPECT_NEAR(m.drive_torque_Nm, r.T, 2e-4 * std::abs(r.W) * 0.3) << "z " << z << " s " << s;
      const WheelSoilForces lugged = wong_reece(kWheel, sand, z, s);
      EXPECT_EQ(wong_reece(grippy, sand, z, s).drawbar_pull_N, lugged.drawbar_pull_N);
      EXPECT_LT(std::abs(m.drive_torque_Nm), std::abs(lugged.drive_torque_Nm));
    }
  }
}

// Wong (2008) 2.7.2: a tyre whose inflation and carcass pressures are below
// the soil's pressure under the rigid wheel flattens; its flat bottom
// stands at the sinkage where the soil's pressure equals them, and the
// stresses never exceed them. Above the rigid wheel's largest stress the
// limit changes nothing: the hand-over is continuous.
TEST(WongReece, ATyreFlattensWhereTheSoilWouldPressItHarderThanItsPressures) {
  const SoilMechanics sand;
  const double z = 0.08;
  WheelShape rigid = kWheel;
  const WheelSoilForces r = wong_reece(rigid, sand, z, 0.2);
  WheelShape soft = kWheel;
  soft.ground_pressure_limit_Pa = 1.0001 * r.max_normal_stress_Pa;
  const WheelSoilForces same = wong_reece(soft, sand, z, 0.2);
  EXPECT_EQ(same.flat_half_angle_rad, 0.0);
  EXPECT_NEAR(same.vertical_N, r.vertical_N, 1e-9 * r.vertical_N);
  soft.ground_pressure_limit_Pa = 0.999 * r.max_normal_stress_Pa;
  const WheelSoilForces just = wong_reece(soft, sand, z, 0.2);
  EXPECT_NEAR(just.vertical_N, r.vertical_N, 0.01 * r.vertical_N);
  soft.ground_pressure_limit_Pa = 0.4 * r.max_normal_stress_Pa;
  const WheelSoilForces flat = wong_reece(soft, sand, z, 0.2);
  EXPECT_GT(flat.flat_half_angle_rad, 0.0);
  EXPECT_LE(flat.max_normal_stress_Pa, soft.ground_pressure_limit_Pa * (1.0 + 1e-9));
  EXPECT_LT(flat.vertical_N, r.vertical_N);
}

// A second pass in the rut: the soil down to the first pass's depth follows
// the stiff reload line, so the wheel sinks into the rut by little more
// than the soil's spring-back.
TEST(WongReece, ASecondPassFollowsTheReloadLine) {
  const SoilMechanics sand;
  const double load = 3000.0;
  const double first = wong_reece_sinkage_m(kWheel, sand, load, 0.0);
  const double modulus = bekker_modulus_Pa(sand, kWheel.width_m);
  SoilHistory rut;
  rut.peak_sinkage_m = first;
  rut.surface_depth_m = plastic_sinkage_m(sand, modulus, first);
  const double second = wong_reece_sinkage_m(kWheel, sand, load, 0.0, rut);
  EXPECT_LT(second, 0.3 * first);
  EXPECT_GT(second, 0.5 * (first - rut.surface_depth_m));
  std::printf("first pass %.4f m deep, rut %.4f m; the second sinks %.4f m into it\n", first, rut.surface_depth_m,
              second);
}

}  // namespace
}  // namespace skidsim::terrain
