// Loading experiments with a closed-form reference, run on the terrain alone
// (a TranslatingBody, no multibody engine): the plate-loading test behind
// Bekker's pressure-sinkage law (3.19; thesis 7.3.1, table 7.6, fig. 7.10)
// and a rigid wheel against Bekker's rigid-wheel sinkage (docs/performance.md,
// "Wheel sinkage"). The terrain tests assert their results and the
// speed-against-error report times them over cell sizes.
#pragma once

#include "terrain/granular_grid.h"
#include "terrain/soil_mechanics.h"
#include "terrain/wheel_soil.h"

namespace skidsim::terrain {

// Soil with Bekker exponent n whose k_phi puts a 1000 kg plate 0.15 m deep
// (k_c = 0), so every n gives sinkages of centimetres, as in table 7.6.
SoilMechanics plate_test_soil(double n);

// Bekker (3.19) for the 1 m x 1 m plate: z = (m g / A / (k_c / b + k_phi))^(1/n).
double bekker_plate_depth_m(const SoilMechanics& soil, double mass_kg);

struct PlateLoadingRun {
  double sinkage_m = 0.0;        // below the layer's top
  double final_speed_m_s = 0.0;  // vertical, at the end
  double supported_N = 0.0;      // the soil's vertical force at the end
  double simulated_s = 0.0;
};

// The plate (0.1 m thick) on `grid`, a flat layer `layer_top_m` high: its
// weight applied over 1 s (a quasi-static plate-loading test) and held
// until it has stopped (10 s in all at most), stepping the grid with it.
// The plate's edges fall off the cell edges, so partly covered cells must
// carry their share.
PlateLoadingRun run_plate_loading(GranularGrid& grid, const SoilMechanics& soil, double mass_kg, double layer_top_m,
                                  double step_dt_s);

// Bekker's rigid-wheel sinkage z0 = [3 W / ((3 - n)(k_c + b k_phi)
// sqrt(D))]^(2/(2n+1)) (docs/performance.md, "Wheel sinkage"): the load
// carried on the front half of the contact only, as for a towed wheel. A
// standing wheel is carried by both halves and sinks 2^(-2/(2n+1)) of it.
double bekker_rigid_wheel_depth_m(const SoilMechanics& soil, double load_N, double radius_m, double width_m);

// A rigid wheel of `mass_kg` on `grid`, a flat layer `layer_top_m` high,
// loaded over 1 s: standing (speed 0) for 6 s, or towed at `speed_m_s`
// for 2.8 m, rolling (its lowest point still). Returns the sinkage below
// the layer's top at the end and the simulated time.
struct WheelLoadingRun {
  double sinkage_m = 0.0;
  double simulated_s = 0.0;
};
WheelLoadingRun run_rigid_wheel(GranularGrid& grid, const SoilMechanics& soil, double mass_kg, double radius_m,
                                double width_m, double speed_m_s, double layer_top_m, double step_dt_s);

// A rigid wheel on `grid` by Wong-Reece (terrain/wheel_contact.h): `mass_kg`
// on the axle (loaded over 0.5 s), towed or driven at `speed_m_s` along +x
// for `travel_m`, free to sink. Driven: the spin is held at
// v / (r (1 - slip)), braked (slip < 0) at v (1 + slip) / r; towed (slip
// NaN): the wheel spins freely (no torque on
// the axle, the spin's inertia that of a uniform disc) and finds its own
// slip. The figures are means over the last 40 % of the travel; the rut is
// pressed by the wheel's contact map as in sessions.
struct SoftWheelRun {
  double sinkage_m = 0.0;        // below the layer's top
  double drawbar_pull_N = 0.0;   // forwards
  double drive_torque_Nm = 0.0;  // what the axle supplies
  double slip = 0.0;             // (r omega - v) / max(r omega, v), measured
  double vertical_N = 0.0;
  double simulated_s = 0.0;
};
// `rim_friction_angle_rad`: a smooth rim's friction on the soil
// (terrain/wheel_soil.h WheelShape; the default, the soil shears).
SoftWheelRun run_soft_wheel(GranularGrid& grid, const SoilMechanics& soil, double mass_kg, double radius_m,
                            double width_m, double slip, double speed_m_s, double travel_m, double layer_top_m,
                            double step_dt_s, double rim_friction_angle_rad = WheelShape::kNoRimSlip);

}  // namespace skidsim::terrain
