// The fed heap (experiments/fed_heap.h) on the automaton alone: at steady
// state the whole feed runs down the slope and off the edge, and the slope
// carries it as the flow law's closed form says,
//   tan beta = tan alpha_I + Q / (v h_r)   (Q above the transport v h_stop),
// evaluated here from the soil's data, at two cell sizes. Against the DEM's
// heap: tests/dem_fed_heap_reference_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/physical_constants.h"
#include "experiments/fed_heap.h"

namespace skidsim::terrain {
namespace {

TEST(FedHeap, TheAutomatonCarriesTheFeedAtTheFlowLawsSlope) {
  const SoilFlowParameters sand;  // dry sand: v h_r = 0.3 m^2/s, v h_stop = 0.005 m^2/s
  const double tan_stop = std::tan(deg_to_rad(sand.stop_angle_deg));
  const double v_hr = sand.rolling_speed_m_per_s * sand.rolling_layer_m;
  for (double cell : {0.1, 0.05})
    for (double q_dem : {0.001, 0.004}) {
      FedHeapCase c;
      c.lambda = 10.0;  // a heap 3.2 m long, Q lambda^(3/2): 0.032 and 0.126 m^2/s
      c.cell_m = cell;
      c.q_m2_s = q_dem;
      c.duration_s = 40.0;  // twice the DEM's: the steeper heap takes that long to fill,
      c.window_from_s = 34.0;  // then its last 6 s
      const FedHeapRun run = run_fed_heap(c, sand);
      const double q = q_dem * std::pow(c.lambda, 1.5);
      ASSERT_GT(q, sand.rolling_speed_m_per_s * sand.min_flow_layer_m);  // the diffusive branch
      const double expected = tan_stop + q / v_hr;
      std::printf("cell %.2f m, Q %.3f m^2/s: tan beta %.4f (closed form %.4f), drift %.1e, outflow / feed %.3f\n", cell, q,
                  run.tan_slope, expected, run.tan_drift, run.outflow_over_feed);
      EXPECT_TRUE(run.books_exact);
      EXPECT_NEAR(run.outflow_over_feed, 1.0, 0.01) << "not yet at steady state";
      EXPECT_LT(std::abs(run.tan_drift), 5.0e-4);
      // The fitted line runs through cell heights sampled a cell apart; its
      // slope is the closed form's within 0.2 % (measured: 0.01 %).
      EXPECT_NEAR(run.tan_slope, expected, 0.002 * expected);
    }
}

}  // namespace
}  // namespace skidsim::terrain
