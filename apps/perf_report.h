// `skidsim bench report`: speed against error (VALIDATION.md), measured in
// this run and written as docs/performance.md with an SVG plot per case:
// for each accuracy case with a reference, a ladder of cell sizes, the
// error against the reference and the cost (wall seconds per simulated
// second, one core). So a user can pick the cheapest cell size that meets
// the error they need.
//
// Cases so far: the repose cone (a point pour; flank slope against the
// stop angle alpha_I, and roundness, diagonals against axes) and the blade
// push (the resistance after 2 m against the finest rung, 50 cells/m).
#pragma once

#include <string>

namespace skidsim::apps {

struct PerfReportJob {
  std::string out_path = "docs/performance.md";  // the SVGs go beside it
  bool quick = false;                            // two rungs per ladder (a test's run), not the whole ladder
};

int write_perf_report(const PerfReportJob& job);

}  // namespace skidsim::apps
