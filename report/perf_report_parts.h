// The pieces `skidsim bench report` (report/perf_report.h) builds its page
// from: a ladder's rung, its table and its SVG plot, the observed order of
// convergence read from a ladder, and a section of the page. Each family of
// cases (apps/perf_*.cpp) returns a ReportSection; write_perf_report puts
// them in order, so one more comparison is one more call.
#pragma once

#include <chrono>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace skidsim::report::perf {

// One rung of a ladder: its setting (a cell size, sub-steps), the error
// against the case's reference and what it cost.
struct Rung {
  std::string label;  // the setting, e.g. "5 cm"
  double cost = 0.0;  // wall seconds per simulated second, or per evaluation (the table says which)
  double error = 0.0;
  std::string detail;
};

// A section of the page: its Markdown (headed "## ...") and the SVG files it
// links to (file name beside the page, content).
struct ReportSection {
  std::string markdown;
  std::vector<std::pair<std::string, std::string>> svgs;
};

// What every section gets: whether the ladders are short (a test's run), a
// scratch folder it may write to, and the page's stem (SVG names start with it).
struct ReportContext {
  bool quick = false;
  std::filesystem::path work_dir;
  std::string stem;
  std::string svg_name(const std::string& what) const { return stem + "_" + what + ".svg"; }
};

// The most wall time one rung of a ladder may take (LadderBudget).
inline constexpr double kRungBudgetS = 60.0;

inline constexpr const char* kCostPerSimulatedSecond = "cost (wall s per simulated s)";

// printf-style formatting of one number.
std::string fmt(const char* format, double v);

// Error against cost on log-log axes, each rung labelled.
std::string svg_plot(const std::string& title, const std::string& error_label, const std::vector<Rung>& rungs,
                     const std::string& cost_label = "cost: wall s per simulated s (one core)");

// Curves on linear axes (y against x), each with its name in a legend;
// `dashed` curves share the colour of the one before them.
struct Curve {
  std::string name;
  std::vector<std::pair<double, double>> points;
  bool dashed = false;
};
std::string svg_curves(const std::string& title, const std::string& x_label, const std::string& y_label,
                       const std::vector<Curve>& curves);

// A Markdown table, a row per rung.
std::string table(const std::vector<Rung>& rungs, const std::string& error_header,
                  const std::string& cost_header = kCostPerSimulatedSecond, const std::string& setting_header = "cells");

// How a ladder's error behaves as the cells shrink, from its numbers.
enum class Trend { kFalls, kFallsOverall, kFlat, kRises };
struct Convergence {
  Trend trend = Trend::kFlat;
  std::vector<double> orders;  // between consecutive rungs: log(e_k-1 / e_k) / log(h_k-1 / h_k)
  double fitted_order = 0.0;   // least-squares slope of log e against log h over the ladder
  std::string reading;         // one sentence with the numbers
};
// `sizes` are the rungs' cell sizes (or time steps), coarsest first; `what`
// names the error in the sentence, `shrinking` what gets smaller down the
// ladder (plural). A ladder that neither falls at every rung nor trends by
// 1.5x or more between its ends (fitted order beyond +-0.3) reads as flat.
Convergence convergence(const std::vector<double>& sizes, const std::vector<Rung>& rungs, const std::string& what,
                        const std::string& shrinking = "cells");

// " " + note, or "" for an empty note (a section's optional last sentence).
inline std::string sentence(const std::string& note) { return note.empty() ? "" : " " + note; }

// Which rungs of a ladder (coarsest first) are affordable: a rung is skipped
// when the wall time predicted for it exceeds `budget_s`, the prediction
// being the last rung's time times its growth over the rung before (two
// rungs always run); every rung finer than a skipped one is skipped too.
class LadderBudget {
 public:
  explicit LadderBudget(double budget_s) : budget_s_(budget_s) {}
  // Whether to run the rung `label`; records why not.
  bool allow(const std::string& label);
  // The wall time the rung just allowed took.
  void ran(double wall_s) { wall_s_.push_back(wall_s); }
  // "" when nothing was skipped, else a sentence naming the rungs and why.
  std::string skipped_note() const;

 private:
  double budget_s_;
  std::vector<double> wall_s_;
  std::vector<std::string> skipped_;
  bool stopped_ = false;
};

// A CSV of numbers with a header row (the DEM reference's results), read by
// column name; column() throws naming the file and column when it is missing.
struct CsvNumbers {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::size_t column(const std::string& name, const std::filesystem::path& path) const;
};
// Throws std::runtime_error naming the file when it cannot be read or a row is short.
CsvNumbers read_csv_numbers(const std::filesystem::path& path);
// A quantity,value,... CSV (dem/calibration/material.csv, the calibration's
// results): its rows' numbers in `value_column` by their first column.
// Throws std::runtime_error naming the file when it cannot be read or a
// value is not a number.
std::map<std::string, double> read_csv_quantities(const std::filesystem::path& path, std::size_t value_column = 1);

// The repository's dem/ (the DEM reference's decks and results), beside the
// assets folder (io::default_assets_dir).
std::filesystem::path repository_dem_dir();

// A job's summary.json in `dir`; throws naming the folder when it is missing.
nlohmann::json read_summary(const std::filesystem::path& dir);

// Wall-clock seconds since `start`.
double seconds_since(std::chrono::steady_clock::time_point start);

// Runs the benchmarks compiled into this binary (bench/, what `skidsim
// bench` runs) whose names match `filter`, those without a time or iteration
// count of their own for at least `min_time_s`, and returns them by name
// (e.g. "BM_CubeContact/10"). Throws if one reports an error.
struct BenchmarkRun {
  double real_s_per_iteration = 0.0;  // wall clock
  std::map<std::string, double> counters;
  std::string label;
};
std::map<std::string, BenchmarkRun> run_benchmarks(const std::string& filter, double min_time_s);

// The wheel sections' four plots, added to `s` under names from `prefix`:
// the worst error against cost, and pull, torque and sinkage against slip
// (perf_wheels.cpp).
struct WheelPlotNames {
  std::string error, pull, torque, sinkage;
};
WheelPlotNames add_wheel_plots(const ReportContext& ctx, const std::string& prefix, const std::string& error_title,
                               const std::vector<Rung>& rungs, const std::vector<Curve>& pull,
                               const std::vector<Curve>& torque, const std::vector<Curve>& sinkage, ReportSection& s);

// The sections of the page, one function per family (apps/perf_*.cpp).
ReportSection repose_cone_section(const ReportContext& ctx);      // perf_report.cpp
ReportSection blade_push_section(const ReportContext& ctx);       // perf_report.cpp
ReportSection bcre_section(const ReportContext& ctx);             // perf_ladders_flow.cpp
ReportSection pile_load_section(const ReportContext& ctx);        // perf_ladders_flow.cpp
ReportSection plate_sinkage_section(const ReportContext& ctx);    // perf_ladders_contact.cpp
ReportSection soft_wheel_section(const ReportContext& ctx);       // perf_wheels.cpp (Wong-Reece wheels)
ReportSection wheels_dem_section(const ReportContext& ctx);       // perf_wheels_dem.cpp (wheels against the DEM reference)
ReportSection thesis_tables_section(const ReportContext& ctx);    // perf_thesis_tables.cpp (tables 7.1, 7.4, 7.5)
ReportSection sessions_section(const ReportContext& ctx);         // perf_sessions.cpp (whole sessions; table 9.3)
ReportSection level_of_detail_section(const ReportContext& ctx);  // perf_level_of_detail.cpp (a big site at rest)
ReportSection digging_dem_section(const ReportContext& ctx);      // perf_digging.cpp (blades against the DEM reference)
ReportSection ground_models_section(const ReportContext& ctx);    // perf_ground_models.cpp (automaton vs slippage)
ReportSection collapse_dem_section(const ReportContext& ctx);     // perf_collapse.cpp (collapsing columns against the DEM reference)

}  // namespace skidsim::report::perf
