// The second ground model: Li & Moshell's soil slippage (seed 002, "Modeling
// soil: realtime dynamic models for soil slippage and manipulation"), a
// Mohr-Coulomb slice model with an explicit velocity per slice. A soil site
// selects it instead of the cellular automaton's avalanche rule
// (SoilFlowParameters::model); docs/terrain_model.md section 6 has the
// derivation, the choices made where the paper is silent, and the
// stability bound.
//
// Per face of a cell, the slice is one cell wide (run d) and as high as the
// surface drop along the steepest descent through that face (the face's
// centred normal and tangential differences, as the automaton uses). The
// paper scans fixed x, y and diagonal planes instead; that makes the settled
// shape follow the grid's directions, which the gradient slice avoids.
#pragma once

#include "terrain/flow_law.h"
#include "terrain/soil_mechanics.h"  // kGravity_m_s2

namespace skidsim::terrain {

// Largest Courant number v dt_sweep / d for which a slippage sweep keeps the
// discrete maximum principle. A face sends at most 1/2 (v dt / d) of its drop
// (the sliding wedge is at most half the slice's height times its run), and
// with four faces the new surface stays a convex combination of the old ones
// while 4 * (1/2) Cr <= 1. The paper states no bound; this one is derived
// here and checked in tests and in the report's stability study.
inline constexpr double kMaxSlideCourant = 0.5;

// The model resolved for one grid and one simulation step.
struct SlippageLaw {
  double cell_size_m = 0.0;
  double phi_rad = 0.0;  // angle of internal friction
  // 2 c cos(phi) / gamma (m): the slice fails where
  // rho sin^2((theta - phi) / 2) exceeds it, (3.4) in closed form below.
  double cohesion_length_m = 0.0;
  // Cap on the sliding wedge's speed: the paper has no dissipation besides
  // the stop when a slice turns stable, so an unbroken slide would
  // accelerate without limit. The flowing layer's speed of the soil
  // (SoilFlowParameters::rolling_speed_m_per_s) bounds it.
  double max_speed_m_s = 0.0;
  int substeps = 1;
  double sweep_dt_s = 0.0;
  double courant_limit = kMaxSlideCourant;  // the Courant number the sub-steps keep
};

// One slice of run `run_m` whose top rises `step_m` (> 0) over it.
struct SliceFailure {
  bool fails = false;
  double critical_angle_rad = 0.0;  // beta_0 of 3.2: the failure plane
  // Height (m) of the wedge above the failure plane at the slice's high end:
  // step - run tan(beta_0). Its area is run * excess / 2.
  double excess_m = 0.0;
  // The wedge's acceleration along the plane, g * (3.7) / (gamma * area),
  // i.e. Newton's law (4.5) with the wedge's mass.
  double accel_m_s2 = 0.0;
};

SliceFailure slice_failure(const SlippageLaw& law, double step_m, double run_m);

// Highest step over a run of `run_m` that stands: run tan(phi) for c = 0;
// with cohesion the root of rho sin^2((theta - phi) / 2) = 2 c cos(phi) /
// gamma, so the critical angle depends on the step's size (section 6).
double critical_step_m(const SlippageLaw& law, double run_m);

// Culmann's critical height of a vertical cut in soil of cohesion c and
// friction angle phi: 4 c / gamma tan(45 deg + phi / 2). The slice model
// reproduces it as the run goes to zero.
double culmann_critical_height_m(double cohesion_Pa, double friction_angle_deg, double unit_weight_N_m3);

// Resolves the model for a grid of `cell_size_m` stepped every `step_dt_s`,
// with the sub-steps that keep v_max dt_sweep / d <= courant_limit *
// bound_fraction. Throws std::invalid_argument giving the bound and the
// sub-steps needed when more than `max_substeps` would be, or when the
// soil's slippage fields are out of range. `courant_limit` above
// kMaxSlideCourant is refused unless `allow_beyond_bound` (the report's
// stability study, which shows what happens past the bound).
SlippageLaw derive_slippage_law(const SoilFlowParameters& soil, double cell_size_m, double step_dt_s, int max_substeps,
                                double bound_fraction = 1.0, double courant_limit = kMaxSlideCourant,
                                bool allow_beyond_bound = false);

}  // namespace skidsim::terrain
