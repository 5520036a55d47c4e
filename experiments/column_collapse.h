// Collapse of a granular column on the terrain alone, measured as the DEM
// reference measures its grains (dem/collapse, dem/tools/collapse.py), so
// the two compare in dimensionless form: run-out (r - r0) / r0, final height
// H / r0, the front against t / sqrt(H0 / g).
//
// An axisymmetric column of radius r0 and height H0 = a r0 stands on a flat
// hard base and is released at t = 0; or (slot) a column r0 long against a
// closed wall at x = 0, one row of cells wide, released along +x. The DEM's
// column is lab-sized (r0 = 0.1 m, 8 mm grains); the grid's is scaled to
// r0 = 1 m so that sessions' cells (5 and 10 cm) are 20 and 10 per radius.
// Collapses of cohesionless grains are near scale-free in these variables
// (Lajeunesse et al. 2004, Lube et al. 2004): the run-out and height depend
// on a and the material's friction, and on r0 / d (Warnett et al. 2014),
// which the fast flow keeps by scaling its grains with r0
// (MomentumFlowParameters::grain_diameter_m). The automaton's rolling-layer
// flux is not scaled (docs/fast_flows.md).
#pragma once

#include <vector>

#include "terrain/granular_grid.h"
#include "terrain/material_exchange.h"
#include "terrain/momentum_flow.h"

namespace skidsim::terrain {

struct CollapseCase {
  bool slot = false;     // quasi-two-dimensional: one row of cells, a wall at x = 0
  // The slot's side walls as the DEM has them, over r0 (0.08 m / 0.1 m), and
  // their friction angle on the soil; the momentum flow rubs on them.
  double slot_gap_over_r0 = 0.8;
  double slot_wall_friction_deg = 0.0;
  double aspect = 1.0;   // a = H0 / r0
  double r0_m = 1.0;     // column radius (tube) or length (slot)
  double cell_m = 0.05;
  double step_dt_s = 0.002;
  double max_time_s = 0.0;  // 0: 40 sqrt(H0 / g), far past the DEM's t_stop
  double frame_dt_s = 0.0;  // the front's sampling; 0: sqrt(H0 / g) / 10
  // Fast flows with momentum (terrain/momentum_flow.h) beside the soil's
  // ground model; off: the ground model alone.
  bool momentum = false;
  MomentumFlowParameters momentum_params;
  // A dropped column (a tube only; 0: standing on the floor): released
  // drop_over_r0 r0 above the floor, it falls as parcels (one per cell and
  // slab of a cell's height, terrain/material_exchange.h) and lands on the
  // empty grid, with the momentum flow when `momentum`.
  double drop_over_r0 = 0.0;
};

// The same measures as dem/tools/collapse.py, in the grid's units.
struct CollapseFrame {
  double t_s = 0.0;
  double front_r99_m = 0.0;      // the distance within which 99 % of the mass lies
  // The grains: the case's momentum_params.grain_diameter_m, else the DEM
  // columns' (0.08 r0).
  double front_edge_m = 0.0;     // the farthest cell at least a quarter grain thick
  double centre_height_m = 0.0;  // the highest column within 1.5 grains of the axis or the wall
  // A tube's deposit: its edge (as front_edge_m, cell by cell) along the
  // grid's axes and along its diagonals from the axis: a round deposit has
  // them alike.
  double edge_along_axes_m = 0.0, edge_along_diagonals_m = 0.0;
};

struct CollapseRun {
  CollapseCase c;
  std::vector<CollapseFrame> frames;
  CollapseFrame final_state;
  // As dem/tools/collapse.py reports them: the front's advance since the
  // release over r0, and the final centre height over r0 (the column's own
  // height at release taken as H0).
  double runout_over_r0 = 0.0;       // front_r99
  double edge_runout_over_r0 = 0.0;  // front_edge
  double final_height_over_r0 = 0.0;
  // The final deposit's volume in bins a cell wide along the distance from
  // the axis (or the slot's wall), a cell in the bin of its centre: where
  // its mass lies.
  std::vector<double> deposit_volume_m3;
  double t_stop_s = 0.0;   // the first step that moved nothing (max_time_s if none)
  bool at_rest = false;
  bool flow_at_rest = false;  // the momentum layer (if any) moved nothing at the end
  bool books_exact = false;  // the ledger balanced at every frame
  double wall_s = 0.0;
  int steps = 0;
};

// Runs the case in `soil` (either ground model) until nothing moves or
// max_time_s. Throws std::invalid_argument for a case the grid cannot hold.
CollapseRun run_column_collapse(const CollapseCase& c, const SoilFlowParameters& soil);

// The published run-out law for axisymmetric collapses on a horizontal
// plane, (r_inf - r0) / r0 = 1.24 a below a = 1.7 and 1.6 a^0.5 above
// (Lube, Huppert, Sparks and Hallworth 2004, "Axisymmetric collapses of
// granular columns", J. Fluid Mech. 508; measured on sand, salt, rice,
// couscous and sugar alike, columns of hundreds of grains per radius).
// A closed form kept beside the experiment as an independent reference.
double published_runout_over_r0(double aspect);

// A tube of aspect ratio `aspect` at r0 = 1 m as a laboratory or a session
// has it: the soil's own grains (hundreds per radius) and its own friction
// on the floor, the fast flow on, the failed mass raining.
CollapseCase laboratory_column_case(double aspect, double cell_m);

// The measures of one state (exposed for the tests).
CollapseFrame measure_collapse(const GranularGrid& grid, const CollapseCase& c, double t_s);
// The volume in bins a cell wide along the distance from the axis (or the
// slot's wall), and the cells' area in each when `area_m2` is given.
std::vector<double> radial_volumes_m3(const GranularGrid& grid, const CollapseCase& c, std::vector<double>* area_m2);

}  // namespace skidsim::terrain
