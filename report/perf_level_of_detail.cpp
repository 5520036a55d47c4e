// Level of detail by need (issue 8), measured in the report's run: a site
// at rest costs (almost) nothing per step, and the loader working in one
// corner of a 100 m x 100 m site costs what it costs on a 20 m site. The
// benchmarks are those of `skidsim bench` (bench/loader_benchmarks.cpp,
// bench/terrain_benchmarks.cpp), run through run_benchmarks.
#include <sstream>

#include "report/perf_report_parts.h"
#include "terrain/granular_grid.h"

namespace skidsim::report::perf {

ReportSection level_of_detail_section(const ReportContext& ctx) {
  const double min_time_s = ctx.quick ? 0.01 : 0.5;
  const auto corner = run_benchmarks("^BM_MachineInACornerOfASite/", min_time_s);
  const auto at_rest = run_benchmarks("^BM_TerrainAtRest/", min_time_s);
  std::ostringstream md;
  md << "## Level of detail by need\n\n"
     << "Only cells whose neighbourhood changed are examined, and a body touches only the cells under it, so a "
        "terrain at rest costs nothing per step and a machine's cost does not grow with the site around it. "
        "Measured here by the benchmarks of `skidsim bench` (wall clock, one core): the loader driving a circle with "
        "its bucket cycling into 0.5 m of dry sand (10 cm cells) in one corner of a 20 m and of a 100 m square site, "
        "and a 2048 x 2048 terrain at rest.\n\n"
     << "| case | cells | per 2 ms step | real-time factor | cells moving |\n|---|---|---|---|---|\n";
  double small_us = 0.0, large_us = 0.0, small_cells = 0.0, large_cells = 0.0;
  for (const auto& [name, run] : corner) {
    const bool large = name.find("/100") != std::string::npos;
    const double us = run.real_s_per_iteration * 1e6;
    (large ? large_us : small_us) = us;
    (large ? large_cells : small_cells) = run.counters.at("cells");
    md << "| loader in a corner of a " << (large ? "100 m" : "20 m") << " site | " << fmt("%.0f", run.counters.at("cells"))
       << " | " << fmt("%.1f", us) << " us | " << fmt("%.1f", run.counters.at("sim_s_per_s")) << "x | "
       << fmt("%.0f", run.counters.at("active_cells")) << " |\n";
  }
  for (const auto& [name, run] : at_rest)
    md << "| terrain at rest, one step | " << fmt("%.0f", 2048.0 * 2048.0) << " | "
       << fmt("%.1f", run.real_s_per_iteration * 1e9) << " ns | | 0 |\n";
  md << "\n";
  if (small_us > 0.0 && large_us > 0.0)
    md << "Measured: the 100 m site's step costs " << fmt("%.2f", large_us / small_us) << " times the 20 m site's, with "
       << fmt("%.0f", large_cells / small_cells) << " times the cells. What differs is the machine's own work (the cells "
       << "moving, sampled at the end of each run, above); the " << fmt("%.0f", large_cells - small_cells)
       << " more cells, at rest away from the machine, are never examined and cost only their memory ("
       << terrain::GranularGrid::kStateBytesPerCell << " bytes each).\n\n";
  ReportSection section;
  section.markdown = md.str();
  return section;
}

}  // namespace skidsim::report::perf
