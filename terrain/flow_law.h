// The avalanche flow law of the granular automaton: how much material a cell
// sends downhill per sweep, derived from physical soil data, and the stability
// bound of the explicit sweep. See docs/terrain_model.md for the derivation.
#pragma once

#include <cstdint>
#include <string>

namespace skidsim::terrain {

// How a soil site's loose material slides: the thesis's cellular automaton
// (this file), or Li & Moshell's slice model (terrain/slippage_law.h).
enum class GroundModel : std::uint8_t { kAutomaton, kSlippage };

// Physical soil data that drives the avalanche rule (thesis 4.1.2, 4.4, 4.5).
struct SoilFlowParameters {
  std::string name = "dry_sand";
  double bulk_density_kg_m3 = 1600.0;  // gamma
  // alpha: slope at which material at rest starts to slide (Mohr-Coulomb,
  // infinite-slope analysis 4.4.1: tan(alpha) = tan(phi) for c = 0).
  double repose_angle_deg = 33.0;
  // alpha_I < alpha: slope at which a running avalanche stops (4.5).
  double stop_angle_deg = 30.0;
  // v: downhill speed of the flowing layer (BCRE, 4.4.2).
  double rolling_speed_m_per_s = 1.0;
  // h_r: thickness of the layer that flows. See docs/terrain_model.md for why
  // this is the failing layer of a slump (decimetres), not a few grains.
  double rolling_layer_m = 0.3;
  // h_stop: the thinnest layer that keeps flowing (Pouliquen 1999: a few to
  // ten grain diameters near the repose angle). Close to alpha_I a flowing
  // cell carries at least this layer at speed v: the flux does not fade away
  // as the slope nears alpha_I, it is a transport (4.4.3) that stops when the
  // slope falls below alpha_I, so avalanches end in finite time.
  double min_flow_layer_m = 0.005;

  GroundModel model = GroundModel::kAutomaton;
  // Mohr-Coulomb strength for the slippage model (2.1): cohesion c and angle
  // of internal friction phi of the soil as it lies; 0 deg takes the repose
  // angle (a cohesionless sand fails at slope > phi). The automaton ignores
  // them. rolling_speed_m_per_s caps the sliding wedge's speed there.
  double slip_cohesion_Pa = 0.0;
  double slip_friction_angle_deg = 0.0;
  double slip_friction_deg() const { return slip_friction_angle_deg > 0.0 ? slip_friction_angle_deg : repose_angle_deg; }
  // A flowing layer's friction on its bed as it slows to rest: the mu_s of
  // the mu(I) law, the angle below which a thick flow on an incline stops
  // (Pouliquen 1999; dem/calibration/chute.in measures it). The fast flow's
  // bed friction (terrain/momentum_flow.h); 0 takes alpha_I. It is not
  // alpha_I itself: the automaton's poured cones stand at alpha_I, while a
  // flowing layer, dilated, slides on to a gentler angle.
  double flowing_friction_angle_deg = 0.0;
  double flowing_friction_deg() const { return flowing_friction_angle_deg > 0.0 ? flowing_friction_angle_deg : stop_angle_deg; }
  // Thin layers stop on steeper slopes (Pouliquen 1999, "Scaling laws in
  // granular flows down rough inclined planes", Phys. Fluids 11):
  //   tan theta_stop(h) = tan theta_1 + (tan theta_2 - tan theta_1) exp(-h / (A d))
  // with theta_1 the flowing friction above, theta_2 the thin-layer limit,
  // A the decay in grains and d the grain diameter. A grain diameter of 0
  // leaves the friction independent of the thickness (a sand's 0.3 mm grains
  // make it so for any layer a fast flow carries).
  double grain_diameter_m = 0.0;
  double thin_layer_friction_angle_deg = 0.0;
  double thin_layer_decay_grains = 0.0;
  // A layer's friction rises with its speed: Jop, Forterre and Pouliquen's
  // (2006, "A constitutive law for dense granular flows", Nature 441, (2))
  // mu(I) on the thin-layer stop friction above, with the layer's inertial
  // number from its depth and mean speed as Pouliquen and Forterre (2002)
  // read it:
  //   mu(h, I) = tan theta_stop(h) + (tan theta_r - tan theta_stop(h)) I / (I_0 + I),
  //   I = u d / (h sqrt(g h)),
  // u the layer's mean speed, h the depth it moves in, theta_r the rate
  // friction angle below; needs the grain diameter. Measured on the DEM's
  // inclined layers as they slow (dem/tools/rate_friction.py). 0: the
  // friction does not rise with speed. Read where the fast flow asks for it
  // (MomentumFlowParameters::rate_friction).
  double rate_friction_angle_deg = 0.0;
  double rate_friction_i0 = 0.0;
  // The angle at which a deep bed of the soil at rest starts to flow by
  // itself (Pouliquen's theta_start for a thick layer; Daerr and Douady
  // 1999): a moving layer carries away only what a flow laid down, or a bed
  // steeper than this (terrain/momentum_flow.h). 0: none, every bed under a
  // moving layer erodes down to the flowing friction.
  double bed_start_angle_deg = 0.0;
  // What a landing keeps of its fall: material that lands from a body at
  // speed V sends out a sheet at c V (a jet on a plate; c = 1 for an ideal
  // fluid, which Cheng et al. 2007 found a dense granular jet to resemble;
  // 0.20 measured on the DEM's jet at twice its radius against the free
  // fall, floor friction included, dem/README.md; terrain/momentum_flow.h;
  // the model's sheet speed is the stagnation flow's c V r / R; a landing
  // whose sheet would stop within a cell does not press). 0: a landing's
  // vertical momentum is lost at the impact.
  double impact_sheet_speed_ratio = 0.0;
};

// Throws std::invalid_argument naming the offending field when a value is out
// of its physical range (negative density, alpha_I >= alpha, ...).
void validate(const SoilFlowParameters& soil);

// The flow law resolved for one grid and one simulation step.
struct FlowLaw {
  double tan_repose = 0.0;     // tan(alpha)
  double tan_stop = 0.0;       // tan(alpha_I)
  // Excess slope below which the flow is a transport of the h_stop layer:
  // h_stop / h_r, i.e. tan(eta) - tan(alpha_I) for the switch angle eta.
  double transport_excess = 0.0;
  // z+ of (4.11) for ONE sweep (a sub-step), metres of height moved per unit
  // of excess slope: z+ = dt_sweep * v * h_r / d.
  double z_plus_per_sweep_m = 0.0;
  int substeps = 1;            // sweeps per simulation step
  double sweep_dt_s = 0.0;
  double cell_size_m = 0.0;

  // Height (m) a flowing cell at slope magnitude `tan_beta` sends downhill in
  // one sweep, before it is split among its downhill neighbours: the rule
  // (4.16) z+ (tan beta - tan alpha_I), diffusive (BCRE) above the switch
  // angle eta, the transport z+ (tan eta - tan alpha_I) between alpha_I and
  // eta, and nothing at or below alpha_I.
  double moved_height_m(double tan_beta) const {
    const double excess = tan_beta - tan_stop;
    const double moved = z_plus_per_sweep_m * (excess > transport_excess ? excess : transport_excess);
    return excess > 0.0 ? moved : 0.0;  // a select, not a branch: the sweep vectorises
  }
};

// Largest z+/d per sweep for which the sweep keeps the discrete maximum
// principle (no new extrema, no checkerboard): every pairwise flux is at most
// (z+/d) times the height difference, a cell has 4 neighbours, so the new
// surface is a convex combination of the old ones when 4 z+/d <= 1.
inline constexpr double kMaxZPlusOverCell = 0.25;

// Resolves the flow law for a grid of `cell_size_m` stepped every `step_dt_s`,
// sub-stepping as the bound asks. Throws std::invalid_argument with a message
// that gives the bound, the sub-steps needed and how to fix the parameters
// when more than `max_substeps` would be needed.
// `bound_fraction` in (0, 1] keeps a margin below the bound (see
// GridSpec::flow_bound_fraction).
FlowLaw derive_flow_law(const SoilFlowParameters& soil, double cell_size_m,
                        double step_dt_s, int max_substeps, double bound_fraction = 1.0);

}  // namespace skidsim::terrain
