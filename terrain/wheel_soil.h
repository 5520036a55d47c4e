// A wheel on soft soil by the rigid-wheel theory of Wong and Reece (1967,
// "Prediction of rigid wheel performance based on the analysis of soil-wheel
// stresses", J. Terramechanics 4(1) and 4(2); Wong, "Theory of Ground
// Vehicles", 4th ed., 2008, sec. 2.7 and 4.x), docs/soil_contact.md "Wheels".
// Plain functions of plain data, SI units; angles from the downward
// vertical through the axle, positive towards the direction of travel.
//
//   normal stress, front (theta_m..theta_1):
//     sigma = p(z_h + r (cos theta - cos theta_1))   p: the soil's loading or
//                                                    reload line (history z_h)
//   rear (theta_2..theta_m), mapped onto the front (Wong-Reece 1967 eq. 7):
//     theta* = theta_1 - (theta - theta_2) / (theta_m - theta_2) (theta_1 - theta_m)
//   the angle of the largest stress moves with slip: theta_m = (c1 + c2 s) theta_1
//   shear (Janosi-Hanamoto): tau = (c + sigma tan phi)(1 - exp(-j / K)),
//     j = r [a (theta_1 - theta) - b (sin theta_1 - sin theta)],
//     a = r omega / max(r omega, v), b = v / max(r omega, v)
//   forces on the wheel:
//     W  = r b_w Int (sigma cos theta + tau sin theta) dtheta   (up)
//     DP = r b_w Int (tau cos theta - sigma sin theta) dtheta   (forward)
//     T  = r^2 b_w Int tau dtheta  (the torque the drive must supply)
//   a smooth rim: c and tan(phi) no more than the interface's 0 and tan(delta)
//
// Slip s = (r omega - v) / max(r omega, v): Wong's slip i = 1 - v / (r omega)
// when driven (0..1), minus the skid 1 - r omega / v when braked (-1..0).
// The shear displacement's clock is the faster of the rim and the ground:
// Wong-Reece's rim clock when driven, the ground's when braked, so a locked
// wheel shears the soil by the distance it slides, not without bound.
#pragma once

#include "terrain/soil_mechanics.h"

namespace skidsim::terrain {

// The soil the wheel meets ahead: the depth of its surface below the
// undisturbed level and the deepest a load has pressed it (a rut from an
// earlier pass: the reload line to that depth, then the loading curve).
struct SoilHistory {
  double surface_depth_m = 0.0;
  double peak_sinkage_m = 0.0;
};

// A pneumatic tyre flattens where the soil would press it harder than its
// inflation and carcass pressures (Wong 2008, sec. 2.7.2): the flat bottom
// stands at the sinkage where the soil's pressure is p_i + p_c. Zero: a
// rigid wheel.
//
// The rim's grip on the soil: a lugged tyre (or a rim coated with the soil)
// shears the soil itself, tau_max = c + sigma tan(phi); a smooth rim slides
// on it first where its friction is the lower, tau_max = sigma tan(delta)
// (Wong 2008, 2.7: the shear parameters are those of the wheel-soil
// interface where it is the weaker), with the soil's K.
struct WheelShape {
  double radius_m = 0.0;
  double width_m = 0.0;
  double ground_pressure_limit_Pa = 0.0;  // p_i + p_c; 0 for a rigid wheel
  double rim_friction_angle_rad = kNoRimSlip;  // delta of the rim on the soil
  static constexpr double kNoRimSlip = 0.5 * kPi;  // the soil shears first (a lugged tyre)
};

struct WheelSoilForces {
  double vertical_N = 0.0;        // W, up
  double drawbar_pull_N = 0.0;    // DP, forward (along the travel)
  double drive_torque_Nm = 0.0;   // T, what the soil resists the spin with
  double entry_rad = 0.0;         // theta_1
  double exit_rad = 0.0;          // theta_2 (<= 0: the rear rebound)
  double max_stress_rad = 0.0;    // theta_m
  double max_normal_stress_Pa = 0.0;
  double contact_length_m = 0.0;  // r (sin theta_1 - sin theta_2)
  double flat_half_angle_rad = 0.0;  // > 0: the tyre is flattened
  double shear_strength_N = 0.0;  // (c A + W tan phi), the lateral bound
};

// The wheel with its lowest point `sinkage_m` below the soil's surface
// ahead, at slip `slip` in [-1, 1]. Takes the soil's Bekker, reload and
// Mohr-Coulomb parameters and its wheel_* coefficients.
//
// Slip sinkage (Lyasko 2010, "Slip sinkage effect in soil-vehicle
// mechanics", J. Terramechanics 47, eq. 12), when the soil asks for it: a
// driven wheel digs the soil under it backwards and sinks deeper than its
// load alone would press it, z = z_0 (1 + s) / (1 - 0.5 s); the stresses are
// those of the sinkage the load presses, z over that factor.
WheelSoilForces wong_reece(const WheelShape& wheel, const SoilMechanics& soil, double sinkage_m, double slip,
                           const SoilHistory& history = {});

// Lyasko's factor (1 + s) / (1 - 0.5 s) for s > 0, 1 otherwise.
double slip_sinkage_factor(double slip);

// The sinkage at which the wheel carries `load_N` at `slip` (bisection on
// W, which grows with sinkage), for reports and the flexible-tyre criterion.
double wong_reece_sinkage_m(const WheelShape& wheel, const SoilMechanics& soil, double load_N, double slip,
                            const SoilHistory& history = {});

}  // namespace skidsim::terrain
