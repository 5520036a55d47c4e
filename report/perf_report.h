// `skidsim bench report`: speed against error (docs/validation.md), measured in
// this run and written as docs/performance.md with an SVG plot per case:
// for each accuracy case with a reference, a ladder of cell sizes (and
// sub-steps where they matter), the error against the reference and the
// cost (wall seconds per simulated second, one core). So a user can pick the
// cheapest cell size that meets the error they need.
//
// Sections (report/perf_report_parts.h; one function each): the repose cone
// and the blade push (this file's .cpp), BCRE diffusion and the pressure
// under a pile (perf_ladders_flow.cpp), plate and wheel sinkage
// (perf_ladders_contact.cpp), the thesis's speed tables 7.1, 7.4 and 7.5 from
// the benchmarks (perf_thesis_tables.cpp), whole sessions' real-time
// factors and table 9.3 (perf_sessions.cpp).
#pragma once

#include <string>

namespace skidsim::report {

struct PerfReportJob {
  std::string out_path = "docs/performance.md";  // the SVGs go beside it
  bool quick = false;                            // two rungs per ladder (a test's run), not the whole ladder
};

int write_perf_report(const PerfReportJob& job);

}  // namespace skidsim::report
