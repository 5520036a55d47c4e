// Tyre forces on firm ground: the Magic Formula (Pacejka, "Tire and Vehicle
// Dynamics", 2006, ch. 4) with combined-slip weighting functions, driven by
// the contact patch's deflection (a first-order relaxation, ch. 7) instead of
// the kinematic slip, so that the forces stay finite and smooth at standstill:
// a stopped tyre on a slope is a spring (no creep), a rolling one reaches the
// steady Magic Formula after about one relaxation length of travel.
//
// Frames: x along the wheel's heading on the ground plane, y along the axle
// projected on it, forces are what the ground exerts on the tyre.
#pragma once

#include "vehicle/loader_description.h"

namespace skidsim::vehicle {

// Velocities of the contact point, m/s, in the contact frame.
struct TyreKinematics {
  double normal_load_N = 0.0;
  double contact_speed_x = 0.0;  // V_cx: the patch's travel along the heading
  double contact_speed_y = 0.0;  // V_cy: lateral scrub
  double rolling_speed = 0.0;    // V_r = Omega * r
};

// Patch deflections (m), the state carried between steps.
struct TyreDeflection {
  double x_m = 0.0, y_m = 0.0;
};

struct TyreForce {
  double longitudinal_N = 0.0, lateral_N = 0.0;
};

// Steady-state Magic Formula with combined slip. `slip_ratio` in [-1, 1]
// (positive: driving), `slip_angle_rad` (positive: the patch moves to -y).
TyreForce magic_formula(const TyreParameters& p, double slip_ratio, double slip_angle_rad, double normal_load_N);

// The slip the deflection stands for: kappa' = u_x / sigma_x, alpha' = atan(u_y / sigma_y).
double deflection_slip_ratio(const TyreParameters& p, const TyreDeflection& u);
double deflection_slip_angle(const TyreParameters& p, const TyreDeflection& u);

// Force on firm ground from the current deflection, with the low-speed
// damping that settles a stopped tyre, bounded by friction.
TyreForce firm_tyre_force(const TyreParameters& p, const TyreDeflection& u, const TyreKinematics& k);

// Soft soil under a tyre. Along the heading: the wheel's drawbar pull by
// Wong-Reece (terrain/wheel_soil.h, computed by the engine at the slip
// deflection_slip_ratio gives: the steady slip of that relaxation is
// Wong's (r omega - v) / max(r omega, v)). Across it: Janosi-Hanamoto shear
// (Wong, Theory of Ground Vehicles, 2.56 / 2.65), tau = (c + sigma tan phi)
// (1 - exp(-j / K)), the shear displacement j growing from 0 at the front of
// the contact to L tan(alpha') at its rear; integrated over the patch,
//   F_y = (c A + W tan phi) [1 - K / (t L) (1 - exp(-t L / K))], t = tan alpha',
// within the soil's strength. Driven by the same patch deflection as the
// Magic Formula: continuous across a firm/soft edge and a spring at
// standstill.
struct SoilShear {
  double cohesion_Pa = 0.0;
  double friction_angle_rad = 0.0;
  double shear_modulus_K_m = 0.025;
  double contact_length_m = 0.0;
};

struct SoilTyreForce {
  TyreForce force;
  bool at_strength = false;  // the soil shears (the wheel slips more than half, or the side force is near its bound)
};

// `k.normal_load_N` is the soil's vertical load on the tyre. The same
// low-speed damping as on firm ground settles it.
SoilTyreForce soil_tyre_force(const TyreParameters& p, const TyreDeflection& u, const SoilShear& soil,
                              const TyreKinematics& k, double contact_area_m2, double drawbar_pull_N);

// Advances the deflection by dt (exact for frozen velocities, so stable for
// any step): du_x/dt = -(V_cx - V_r) - u_x max(|V_cx|, |V_r|) / sigma_x,
// du_y/dt = -V_cy - u_y (max(|V_cx|, |V_r|) + |V_cy|) / sigma_y.
// The decay rates bound the steady slips to |kappa'| <= 1, |tan alpha'| <= 1.
void advance_deflection(const TyreParameters& p, const TyreKinematics& k, double dt_s, TyreDeflection& u);

}  // namespace skidsim::vehicle
