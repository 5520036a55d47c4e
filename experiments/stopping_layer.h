// A flowing layer coming to rest on level ground (dem/calibration/stopping.in)
// on the grid: a long layer of uniform depth set moving at one speed over a
// deep bed of its own grains at rest, or on the bare floor, and left to the
// fast flow owning its cells (terrain/momentum_flow.h, owns_cells) until it
// stops. How far its mass centre travels and when it stops, over the
// deceleration a = g tan(theta_stop(h)) its friction gives a layer h deep
// (the soil's thin-layer law, or the floor's friction), are the deposition's
// dimensionless signature (docs/fast_flows.md, "A layer coming to rest"): a
// plug sliding to rest has 1/2 and 1, a layer laying its base down at the
// static/flowing interface 2/3 and 2.
#pragma once

#include "terrain/flow_law.h"
#include "terrain/momentum_flow.h"

namespace skidsim::terrain {

struct StoppingLayerCase {
  double layer_m = 0.128;      // the DEM's 16 grains of 8 mm
  double speed_m_s = 0.72;     // the layer's mean speed at the start
  double cell_m = 0.05;
  double step_dt_s = 0.002;
  double length_m = 8.0;       // the strip; the layer covers its middle three quarters
  bool on_floor = false;       // on the bare floor (floor_friction_deg) instead of a deep bed
  double floor_friction_deg = 0.0;   // the floor's, on_floor (the DEM's: report/dem_columns.h)
  MomentumFlowParameters::Deposition deposition = MomentumFlowParameters::Deposition::kInterface;
  double max_time_s = 3.0;
};

struct StoppingLayerRun {
  // Over the middle third of the layer, away from its ends: the mass centre's
  // travel (the momentum of its flowing layer over the whole layer's mass,
  // summed over the steps) until its flowing speed falls under a twentieth
  // of its first (t_stop_s), as dem/tools/stopping.py measures the DEM's.
  double travel_m = 0.0;
  double t_stop_s = 0.0;
  // The deceleration the flow's friction gives the layer (m/s^2):
  // g tan(theta_stop(h)) on the bed (MomentumFlow::bed_friction_tan), g
  // tan(delta_floor) on the floor.
  double deceleration_m_s2 = 0.0;
  double travel_ratio = 0.0;     // travel a / u0^2
  double stop_time_ratio = 0.0;  // t_stop a / u0
  bool stopped = false;
  bool books_exact = false;
};

// `soil`: dem_sand (its grain diameter the DEM's).
StoppingLayerRun run_stopping_layer(const StoppingLayerCase& c, const SoilFlowParameters& soil);

}  // namespace skidsim::terrain
