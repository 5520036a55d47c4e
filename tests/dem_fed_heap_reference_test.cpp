// A pour onto a heap against the stored LIGGGHTS heap fed at known rates
// (dem/calibration/fed_heap.in, results/fed_heap_summary.csv;
// scripts/dem_reference.sh, stages fed_heap and fed_heap_post): the slope the
// heap stands at for each feed Q, skidsim's heap the DEM's scaled by 10 as
// the collapsing columns are (experiments/fed_heap.h), at the sessions' 10
// and 5 cm cells, in dem_sand as the columns take it.
//
// What the DEM shows (docs/fast_flows.md, "The slow regime against a fed
// heap"): it sheds its feed in surges, fed at up to 0.002 m^2/s between
// 38-42 and 32-35 deg (the slowest feeds' stop near the pile's repose angle),
// fed faster in smaller, more frequent ones, and its mean slope falls as
// the feed grows, from 38.7 deg at 0.0005 to 31.8 deg at 0.032 m^2/s, a
// heap in the open (no side walls; heaps between walls steepen with the
// flux). The automaton's flux law is a diffusion, its slope rising with Q
// (tan alpha_I + Q / (v h_r)), without the surges: within 5 deg of the
// DEM's mean up to 0.002 m^2/s (tested at 5.5), 11-43 deg too steep
// beyond. With the fast flow the feed
// lands with its fall and runs down as a layer (from 0.001 m^2/s at 10 cm,
// from 0.002 at 5 cm), on a slope that rises with Q from 27 to 31 deg:
// 6.2-7.4 deg under the DEM's at 0.004-0.008 m^2/s, within 1.1 deg at
// 0.032. The bounds hold what is reached; tighten them as the model
// improves.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "experiments/fed_heap.h"
#include "io/soil_table.h"
#include "report/dem_columns.h"
#include "report/perf_report_parts.h"

namespace skidsim::report::perf {
namespace {

TEST(DemFedHeap, ThePourOntoAHeapAgainstTheDemsHeap) {
  const std::vector<DemFedHeap> dem = read_dem_fed_heap(repository_dem_dir());
  ASSERT_GE(dem.size(), 4u);
  const terrain::SoilFlowParameters sand = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  const DemFedHeap& slowest = dem.front();
  const DemFedHeap& fastest = dem.back();
  // The reference itself: fed eight times faster or more, the DEM's heap
  // stands lower.
  ASSERT_GE(fastest.q_m2_s, 8.0 * slowest.q_m2_s);
  EXPECT_LT(slope_deg(fastest.tan_mean), slope_deg(slowest.tan_mean) - 3.0);
  for (double cell : {0.1, 0.05}) {
    for (const DemFedHeap& d : dem) {
      double slope[2];
      for (int momentum = 0; momentum < 2; ++momentum) {
        const terrain::FedHeapRun run = terrain::run_fed_heap(dem_fed_heap_case(d, cell, momentum == 1), sand);
        // Averaged over the DEM's window (from 6 s on), the heap's start
        // included: the slowest feed's DEM heap still gains mass in it too.
        EXPECT_TRUE(run.books_exact);
        slope[momentum] = slope_deg(run.tan_slope);
      }
      std::printf("cell %.2f m, Q %g m^2/s: DEM %.1f [%.1f-%.1f] deg, automaton %.1f deg, with the fast flow %.1f deg\n", cell,
                  d.q_m2_s, slope_deg(d.tan_mean), slope_deg(d.tan_p05), slope_deg(d.tan_p95), slope[0], slope[1]);
      // The automaton alone, where the DEM's heap avalanches at its steepest
      // (Q up to 0.002): within 5.5 deg of the DEM's mean (measured 4.8 and 1.6
      // deg under, 3.1 over). Fed faster it stands 11-43 deg too steep
      // (printed).
      if (d.q_m2_s <= 0.002) {
        EXPECT_LT(std::abs(slope[0] - slope_deg(d.tan_mean)), 5.5) << "Q " << d.q_m2_s << ", cell " << cell;
      }
      if (d.q_m2_s >= 0.004) {
        // Fed fast, the pour runs as a layer, under the DEM's slope and
        // within 8 deg of it (measured 0.8-7.4 deg under).
        EXPECT_LT(slope[1], slope_deg(d.tan_mean)) << "Q " << d.q_m2_s << ", cell " << cell;
        EXPECT_GT(slope[1], slope_deg(d.tan_mean) - 8.0) << "Q " << d.q_m2_s << ", cell " << cell;
      }
      // At the fastest feed within 2 deg (measured 0.8 / 1.1 deg under).
      if (&d == &fastest) {
        EXPECT_NEAR(slope[1], slope_deg(d.tan_mean), 2.0) << "cell " << cell;
      }
    }
  }
}

}  // namespace
}  // namespace skidsim::report::perf
