// The thesis's speed tables 7.1, 7.4 and 7.5 side by side with today's
// figures, measured in the report's run by the benchmarks `skidsim bench`
// runs (bench/terrain_benchmarks.cpp, bench/contact_benchmarks.cpp; compiled
// into this binary): Google Benchmark's runner, a filter and a reporter that
// keeps the runs instead of printing them.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

#include "report/perf_report_parts.h"

namespace skidsim::report::perf {
namespace {

// The thesis's figures (2008, Intel Pentium 4 HT 3.4 GHz), in ms. Table 7.1:
// one update of an N x N automaton with every cell active, N = 5..30.
const std::map<int, double> kTable71Ms = {{5, 0.019}, {10, 0.088}, {15, 0.171}, {20, 0.272}, {25, 0.403}, {30, 0.550}};
// Table 7.4: contact and reaction forces of a unit cube resting on the
// automaton, N cells per metre.
const std::map<int, double> kTable74Ms = {{5, 0.02037},  {10, 0.04805}, {15, 0.09137},
                                          {20, 0.16653}, {25, 0.28971}, {30, 0.52715}};
// Table 7.5: one step of the cube pushed horizontally through a 2 m x 6 m
// patch, by N cells per metre (rows) and its depth d0 = 0.10..0.30 m (columns).
const std::vector<int> kDepthsCm = {10, 15, 20, 25, 30};
const std::map<int, std::vector<double>> kTable75Ms = {
    {5, {0.058256, 0.059008, 0.0606, 0.061128, 0.060964}},      {10, {0.161752, 0.185186, 0.175581, 0.173528, 0.17658}},
    {15, {0.334178, 0.34078, 0.345908, 0.348218, 0.356416}},    {20, {0.579922, 0.591814, 0.606, 0.619512, 0.634594}},
    {25, {0.944118, 0.972844, 0.982218, 1.000694, 1.027596}},   {30, {1.317558, 1.344494, 1.353386, 1.348878, 1.372106}}};

// Keeps every run (by name) instead of printing it.
class KeepingReporter : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.run_type != Run::RT_Iteration) continue;
      if (r.error_occurred) throw std::runtime_error("performance report: benchmark " + r.benchmark_name() + ": " + r.error_message);
      BenchmarkRun m;
      m.real_s_per_iteration = r.real_accumulated_time / static_cast<double>(r.iterations);
      for (const auto& [name, counter] : r.counters) m.counters[name] = counter.value;
      m.label = r.report_label;
      results[r.benchmark_name()] = m;
    }
  }
  std::map<std::string, BenchmarkRun> results;
};

std::string alternatives(const std::vector<int>& values) {
  std::string s;
  for (const int v : values) s += (s.empty() ? "" : "|") + std::to_string(v);
  return "(" + s + ")";
}

// The first result whose name matches `pattern`.
const BenchmarkRun* find(const std::map<std::string, BenchmarkRun>& results, const std::string& pattern) {
  const std::regex re(pattern);
  for (const auto& [name, m] : results)
    if (std::regex_search(name, re)) return &m;
  return nullptr;
}

// The thesis's time over today's, over a table: each cell's text, and the range.
class RatioRange {
 public:
  std::string add(double thesis_s, double today_s) {
    if (!(today_s > 0.0)) return "-";
    const double r = thesis_s / today_s;
    lo_ = std::min(lo_, r), hi_ = std::max(hi_, r), ++count_;
    return fmt("%.1fx", r);
  }
  int count() const { return count_; }
  std::string reading(const std::string& what) const {
    if (count_ == 0) return "Nothing measured for " + what + ".";
    const std::string range = lo_ == hi_ ? fmt("%.1f", lo_) : fmt("%.1f", lo_) + " to " + fmt("%.1f", hi_);
    return "For " + what + ", the thesis's time over today's is " + range + " over the " + std::to_string(count_) +
           " measured cases" + (lo_ > 1.0 ? ": faster today in every one." : hi_ < 1.0 ? ": slower today in every one." : ".");
  }

 private:
  double lo_ = 1e300, hi_ = 0.0;
  int count_ = 0;
};

}  // namespace

std::map<std::string, BenchmarkRun> run_benchmarks(const std::string& filter, double min_time_s) {
  // The runner's flags: benchmarks without a fixed iteration count or time
  // of their own run for at least `min_time_s`.
  std::string program = "skidsim-bench-report", min_time = "--benchmark_min_time=" + fmt("%g", min_time_s);
  std::vector<char*> argv = {program.data(), min_time.data()};
  int argc = static_cast<int>(argv.size());
  benchmark::Initialize(&argc, argv.data());
  KeepingReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter, filter);
  benchmark::Shutdown();
  return reporter.results;
}

ReportSection thesis_tables_section(const ReportContext& ctx) {
  const std::vector<int> n71 = ctx.quick ? std::vector<int>{5, 30} : std::vector<int>{5, 10, 15, 20, 25, 30};
  const std::vector<int> n74 = ctx.quick ? std::vector<int>{5, 10} : std::vector<int>{5, 10, 15, 20, 25, 30};
  const std::vector<int> n75 = ctx.quick ? std::vector<int>{5, 10} : std::vector<int>{5, 10, 15, 20, 25, 30};
  const std::vector<int> d75 = ctx.quick ? std::vector<int>{10, 20} : kDepthsCm;
  const std::string filter = "^BM_AllActiveSweep/" + alternatives(n71) + "$|^BM_CubeContact/" + alternatives(n74) +
                             "$|^BM_CubePush/cells_per_m:" + alternatives(n75) + "/d0_cm:" + alternatives(d75) + "/";
  const std::map<std::string, BenchmarkRun> results = run_benchmarks(filter, ctx.quick ? 0.01 : 0.3);

  std::string md = "## The thesis's speed tables, today\n\nThe thesis's figures (2008: an Intel Pentium 4 HT at 3.4 GHz) beside "
                   "the same experiments measured in this run by the benchmarks of `skidsim bench` (Google Benchmark; "
                   "wall-clock time, one core). Ratio: the thesis's time over today's (above 1: faster today).\n\n";
  // Table 7.1: BM_AllActiveSweep/N, a 60 deg plane draining over an open edge.
  md += "### Table 7.1: automaton update, every cell active\n\nOne step of an N x N automaton whose every cell is unstable (a 60 "
        "deg plane draining over an open edge; `BM_AllActiveSweep`).\n\n| N x N cells | thesis (ms) | today (ms) | today (ns per "
        "cell visit) | ratio |\n|---|---|---|---|---|\n";
  RatioRange r71;
  for (const int n : n71) {
    const BenchmarkRun* m = find(results, "^BM_AllActiveSweep/" + std::to_string(n) + "$");
    const double thesis_s = 1e-3 * kTable71Ms.at(n);
    md += "| " + std::to_string(n) + " x " + std::to_string(n) + " | " + fmt("%.3f", 1e3 * thesis_s) + " | ";
    md += m ? fmt("%.4f", 1e3 * m->real_s_per_iteration) + " | " + fmt("%.1f", 1e9 * m->counters.at("per_cell")) + " | " +
                  r71.add(thesis_s, m->real_s_per_iteration) + " |\n"
            : "not run | | |\n";
  }
  md += "\n" + r71.reading("the all-active update") + "\n\n";
  // Table 7.4: BM_CubeContact/N.
  md += "### Table 7.4: contact map and reaction of a resting cube\n\nA 1 m cube of 1 t settled on 0.4 m of dry sand, N cells "
        "per metre: one contact map and reaction (`BM_CubeContact`).\n\n| N (cells/m) | thesis (ms) | today (ms) | cells in "
        "contact | ratio |\n|---|---|---|---|---|\n";
  RatioRange r74;
  for (const int n : n74) {
    const BenchmarkRun* m = find(results, "^BM_CubeContact/" + std::to_string(n) + "$");
    const double thesis_s = 1e-3 * kTable74Ms.at(n);
    md += "| " + std::to_string(n) + " | " + fmt("%.5f", 1e3 * thesis_s) + " | ";
    md += m ? fmt("%.5f", 1e3 * m->real_s_per_iteration) + " | " + fmt("%.0f", m->counters.at("contact_cells")) + " | " +
                  r74.add(thesis_s, m->real_s_per_iteration) + " |\n"
            : "not run | | |\n";
  }
  md += "\n" + r74.reading("the resting cube's contact") + "\n\n";
  // Table 7.5: BM_CubePush/cells_per_m:N/d0_cm:D.
  md += "### Table 7.5: the cube pushed through a 2 m x 6 m patch\n\nThe cube pushed at 1 m/s for 4 m with its underside d0 "
        "below the surface: one whole step (contact map, reaction, the soil pushed into the wedge, the avalanche sweep; "
        "`BM_CubePush`, 2000 steps). Each cell: thesis ms / today ms (ratio).\n\n| N (cells/m) |";
  for (const int d : d75) md += " d0 = " + fmt("%.2f", 0.01 * d) + " m |";
  md += "\n|---|";
  for (std::size_t k = 0; k < d75.size(); ++k) md += "---|";
  md += "\n";
  RatioRange r75;
  for (const int n : n75) {
    md += "| " + std::to_string(n) + " |";
    for (const int d : d75) {
      const BenchmarkRun* m = find(results, "^BM_CubePush/cells_per_m:" + std::to_string(n) + "/d0_cm:" + std::to_string(d) + "/");
      const std::size_t column = static_cast<std::size_t>(std::find(kDepthsCm.begin(), kDepthsCm.end(), d) - kDepthsCm.begin());
      const double thesis_s = 1e-3 * kTable75Ms.at(n)[column];
      md += " " + fmt("%.3f", 1e3 * thesis_s) + " / " +
            (m ? fmt("%.3f", 1e3 * m->real_s_per_iteration) + " (" + r75.add(thesis_s, m->real_s_per_iteration) + ") |" : "not run |");
    }
    md += "\n";
  }
  md += "\n" + r75.reading("the push") + "\n\n";
  if (r71.count() + r74.count() + r75.count() == 0) throw std::runtime_error("performance report: none of the thesis's benchmarks ran");
  if (ctx.quick) md += "(Quick run: only some of the thesis's N and d0 were measured.)\n\n";
  return {md, {}};
}

}  // namespace skidsim::report::perf
