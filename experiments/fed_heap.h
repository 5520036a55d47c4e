// The fed heap (dem/calibration/fed_heap.in) on the grid: the slope a heap
// stands at while it carries a flux Q, against the DEM's. One row of cells L long against a wall at x = 0, open at x = L
// (material that reaches it falls off, as the DEM's grains leave its box);
// material rains onto the cells beside the wall at Q per metre of width. At
// steady state Q runs down the whole slope, and the automaton's flux law
// (terrain/flow_law.h, (4.16)) says the slope carries it at
//   tan beta = tan alpha_I + Q / (v h_r)   (Q above v h_stop)
// Lengths are lambda times the DEM's, times sqrt(lambda) times the DEM's and
// Q lambda^(3/2) times the DEM's (Froude scaling);
// the soil is taken as the collapsing columns take it
// (experiments/column_collapse.h): the automaton's parameters as they are,
// the fast flow's grains (and h_stop with them) scaled with lambda.
#pragma once

#include "terrain/flow_law.h"

namespace skidsim::terrain {

struct FedHeapCase {
  double q_m2_s = 0.001;          // the DEM's feed: m^3/s of bulk soil per metre of width
  double lambda = 1.0;            // the model's lengths over the DEM's
  double cell_m = 0.05;           // at the model's scale
  double step_dt_s = 0.002;
  // The DEM deck's (fed_heap.in): heap length, the feed's band off the wall,
  // the slope at the start, the run and the averaging window (DEM scale).
  double length_m = 0.32;
  double feed_from_m = 0.005, feed_to_m = 0.045;
  // Where the feed's grains start (the middle of the deck's insertion band,
  // 0.10 m over its initial heap's top at the wall) and how fast (down).
  double feed_height_m = 0.34, feed_speed_m_s = 0.5;
  double initial_tan = 0.737;
  double duration_s = 20.0;
  double window_from_s = 6.0;  // the slope is averaged from here to the end, as fed_heap.py does
  // The slope's least-squares line, as dem/tools/fed_heap.py fits it: from
  // 0.08 m off the wall to 0.06 m short of the edge (DEM scale).
  double fit_from_m = 0.08, fit_to_edge_m = 0.06;
  // Fast flows with momentum (terrain/momentum_flow.h) beside the automaton:
  // the feed lands with its fall (MomentumFlow::land, as a load poured from
  // a body in a session) and what fails past the core's start angle runs
  // as a layer. Off: the automaton alone.
  bool momentum = false;
};

struct FedHeapRun {
  double tan_slope = 0.0;     // averaged over the window, from window_from_s on
  double tan_drift = 0.0;     // the window's second half's mean less its first's
  double outflow_over_feed = 0.0;  // over the window: 1 at steady state
  bool books_exact = false;
};

// `soil`: dem_sand, its grain diameter the DEM's.
FedHeapRun run_fed_heap(const FedHeapCase& c, const SoilFlowParameters& soil);

}  // namespace skidsim::terrain
