#include "report/perf_report.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "report/perf_report_parts.h"
#include "jobs/pour_job.h"
#include "jobs/push_job.h"
#include "io/atomic_file.h"

namespace skidsim::report {
namespace perf {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

}  // namespace

// The repose cone: 600 kg poured at a point on a 6 m yard settles to a cone
// whose flank is the stop angle alpha_I (thesis 7.1), round.
ReportSection repose_cone_section(const ReportContext& ctx) {
  std::vector<Rung> slope, roundness;
  double alpha_i = 30.0;
  const std::vector<double> ladder =
      ctx.quick ? std::vector<double>{0.2, 0.1} : std::vector<double>{0.2, 0.1, 0.05, 0.025, 0.0125};
  std::vector<double> cells;  // the rungs run
  LadderBudget budget(kRungBudgetS);
  for (const double c : ladder) {
    if (!budget.allow(fmt("%g cm", c * 100.0))) continue;
    const auto started = std::chrono::steady_clock::now();
    jobs::PourJob p;
    p.cell_size_m = c;
    p.site_size_m = 6.0;
    p.pour_rate_kg_per_s = 100.0;
    p.pour_duration_s = 6.0;
    p.out_dir = (ctx.work_dir / ("pour_" + fmt("%g", c))).string();
    if (jobs::run_pour_job(p) != 0) throw std::runtime_error("performance report: the pour at " + fmt("%g", c) + " m failed");
    const json s = read_summary(p.out_dir);
    alpha_i = s["soil"]["stop_angle_deg"].get<double>();
    const json& r = s["result"];
    const double cost = s["performance"]["wall_time_s"].get<double>() / r["sim_time_s"].get<double>();
    const std::string label = fmt("%g cm", c * 100.0);
    slope.push_back({label, cost, std::abs(r["pile_flank_slope_deg"].get<double>() - alpha_i),
                     "flank " + fmt("%.2f", r["pile_flank_slope_deg"].get<double>()) + " deg, " +
                         fmt("%.0f", s["performance"]["max_active_cells"].get<double>()) + " cells moving at most"});
    const double axes = r["pile_radius_axes_m"].get<double>(), diag = r["pile_radius_diagonals_m"].get<double>();
    roundness.push_back({label, cost, 100.0 * std::abs(diag - axes) / axes,
                         "radius " + fmt("%.3f", axes) + " m along the axes, " + fmt("%.3f", diag) + " m along the diagonals"});
    budget.ran(seconds_since(started));
    cells.push_back(c);
  }
  const Convergence cs = convergence(cells, slope, "flank error"), cr = convergence(cells, roundness, "roundness error");
  ReportSection out;
  const std::string svg_slope = ctx.svg_name("repose_slope"), svg_round = ctx.svg_name("repose_roundness");
  out.svgs.emplace_back(svg_slope, svg_plot("Repose cone: flank against alpha_I", "error (deg)", slope));
  out.svgs.emplace_back(svg_round, svg_plot("Repose cone: roundness", "diagonal vs axis radius (%)", roundness));
  out.markdown = "## Repose cone\n\n600 kg of dry sand poured at a point (100 kg/s for 6 s) on a 6 m yard, run until at rest. "
                 "Reference: the flank settles at the stop angle alpha_I = " +
                 fmt("%g", alpha_i) + " deg (thesis 4.5, 7.1); a round cone has equal radii along the axes and the diagonals.\n\n" +
                 table(slope, "flank error (deg)") + "\n![flank error against cost](" + svg_slope + ")\n\n" +
                 table(roundness, "roundness error (%)") + "\n![roundness against cost](" + svg_round + ")\n\nReading it: " +
                 cr.reading;
  if (cr.trend == Trend::kFalls || cr.trend == Trend::kFallsOverall)
    out.markdown += " The automaton's four-neighbour flow makes a coarse cone square; finer cells round it.";
  out.markdown += " " + cs.reading;
  if (cs.trend != Trend::kFalls && slope.size() >= 2) {
    // The floor: the error's range from the second rung down.
    double lo = 1e300, hi = 0.0;
    for (std::size_t k = 1; k < slope.size(); ++k) lo = std::min(lo, slope[k].error), hi = std::max(hi, slope[k].error);
    out.markdown += " From " + slope[1].label + " down the flank stays " + fmt("%.2f", lo) + "-" + fmt("%.2f", hi) +
                    " deg from alpha_I, a floor that finer cells do not lower: the flank's slope is measured over the cells "
                    "between apex and foot of the settled cone, and the automaton stops avalanches at alpha_I whatever the "
                    "cells, so " + slope[1].label + " already gets as close as the measure allows.";
  }
  out.markdown += sentence(budget.skipped_note()) + "\n\n";
  return out;
}

// The blade push (thesis fig. 7.12): the resistance after 2 m against the
// finest rung's.
ReportSection blade_push_section(const ReportContext& ctx) {
  const std::vector<double> ladder = ctx.quick ? std::vector<double>{5, 10, 20} : std::vector<double>{5, 10, 20, 30, 50, 80};
  std::vector<double> densities;  // the rungs run
  std::vector<std::pair<double, double>> resistance;  // cells/m, N
  std::vector<double> push_cost;
  LadderBudget budget(kRungBudgetS);
  for (const double d : ladder) {
    if (!budget.allow(fmt("%g cells/m", d))) continue;
    const auto started = std::chrono::steady_clock::now();
    densities.push_back(d);
    jobs::PushJob p;
    p.cells_per_m = d;
    p.distance_m = 2.0;
    p.out_dir = (ctx.work_dir / ("push_" + fmt("%g", d))).string();
    if (jobs::run_push_job(p) != 0) throw std::runtime_error("performance report: the push at " + fmt("%g", d) + " cells/m failed");
    const json s = read_summary(p.out_dir);
    resistance.emplace_back(d, s["result"]["resistance_at_end_N"].get<double>());
    push_cost.push_back(s["performance"]["us_per_step"].get<double>() * 1e-6 / 0.002);
    budget.ran(seconds_since(started));
  }
  const double reference_N = resistance.back().second;
  std::vector<Rung> push;
  std::vector<double> sizes;
  for (std::size_t k = 0; k + 1 < resistance.size(); ++k) {
    push.push_back({fmt("%g/m", resistance[k].first), push_cost[k], 100.0 * std::abs(resistance[k].second - reference_N) / reference_N,
                    fmt("%.0f N", resistance[k].second)});
    sizes.push_back(1.0 / resistance[k].first);
  }
  const Convergence c = convergence(sizes, push, "resistance's difference from the finest rung");
  ReportSection out;
  const std::string svg = ctx.svg_name("push");
  out.svgs.emplace_back(svg, svg_plot("Blade push: resistance after 2 m", "error against " + fmt("%g", densities.back()) + " cells/m (%)", push));
  out.markdown = "## Blade push\n\nA 1 m blade 0.2 m deep pushed 2 m at 1 m/s through 0.4 m of dry sand (thesis fig. 7.12; "
                 "`skidsim push`). There is no closed form once soil piles up in front, so the reference is the finest rung, " +
                 fmt("%g", densities.back()) + " cells/m (" + fmt("%g", 100.0 / densities.back()) + " cm cells): " +
                 fmt("%.0f", reference_N) + " N.\n\n" +
                 table(push, "resistance error (%)") + "\n![resistance error against cost](" + svg + ")\n\nReading it: " + c.reading +
                 " At " + fmt("%g", densities.front()) + " cells/m the blade's 0.2 m is " + fmt("%.0f", 0.2 * densities.front()) +
                 " cell(s) deep, so the pile in front is blocky";
  if (c.trend != Trend::kFalls)
    out.markdown += "; between the finer rungs what is left comes from where the blade's edge falls between cell rows, so it "
                    "need not fall at every rung";
  out.markdown += "." + sentence(budget.skipped_note()) + "\n\n";
  return out;
}

}  // namespace perf

int write_perf_report(const PerfReportJob& job) {
  namespace fs = std::filesystem;
  const fs::path out = job.out_path;
  const fs::path folder = out.has_parent_path() ? out.parent_path() : fs::path(".");
  perf::ReportContext ctx;
  ctx.quick = job.quick;
  ctx.work_dir = fs::temp_directory_path() / ("skidsim_perf_" + std::to_string(::getpid()));
  ctx.stem = out.stem().string();
  fs::create_directories(ctx.work_dir);
  const auto started = std::chrono::steady_clock::now();

  // The page's sections, in order: one call each. Each measures its own
  // cases in this run.
  using Section = perf::ReportSection (*)(const perf::ReportContext&);
  const std::vector<std::pair<const char*, Section>> families = {
      {"repose cone", perf::repose_cone_section},
      {"blade push", perf::blade_push_section},
      {"digging forces against the DEM", perf::digging_dem_section},
      {"BCRE diffusion", perf::bcre_section},
      {"pressure under a pile", perf::pile_load_section},
      {"plate sinkage", perf::plate_sinkage_section},
      {"wheels on soft soil", perf::soft_wheel_section},
      {"wheels against the DEM", perf::wheels_dem_section},
      {"thesis tables 7.1, 7.4, 7.5", perf::thesis_tables_section},
      {"whole sessions, table 9.3", perf::sessions_section},
      {"level of detail", perf::level_of_detail_section},
      {"two ground models", perf::ground_models_section},
      {"collapsing columns against the DEM", perf::collapse_dem_section},
  };
  std::vector<perf::ReportSection> sections;
  std::string timings;
  for (const auto& [name, build] : families) {
    const auto t0 = std::chrono::steady_clock::now();
    sections.push_back(build(ctx));
    const double took = perf::seconds_since(t0);
    timings += std::string(timings.empty() ? "" : ", ") + name + " " + perf::fmt("%.0f s", took);
    std::cout << "performance report: " << name << " in " << perf::fmt("%.1f", took) << " s\n" << std::flush;
  }

  fs::create_directories(folder);
  std::vector<std::string> svg_names;
  for (const perf::ReportSection& s : sections)
    for (const auto& [name, svg] : s.svgs) {
      io::write_text_atomically((folder / name).string(), svg);
      svg_names.push_back(name);
    }
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  const double took_s = perf::seconds_since(started);
  std::ostringstream md;
  md << "# Speed against error\n\n"
     << "Generated by `build/skidsim bench report" << (job.quick ? " --quick" : "") << "` on " << date << ", on a machine with "
     << std::thread::hardware_concurrency() << " cores (one used), in " << perf::fmt("%.0f", took_s) << " s (" << timings
     << "); every number below comes from that run. Regenerate it the same way; the figures move by up to 30 % between runs "
        "on a shared machine (compare within one page).\n\n"
     << "Cost is wall-clock seconds per simulated second on one core (below 1: faster than real time), except where a table "
        "says per evaluation (a static case). Pick the cheapest cells that meet the error you need. Ladders run over cells of "
        "20, 10, 5, 2.5 and 1.25 cm where the case allows (each section says which it skipped and why)"
     << (job.quick ? "; this quick run keeps two rungs per ladder" : "") << ".\n\n";
  for (const perf::ReportSection& s : sections) md << s.markdown;
  io::write_text_atomically(out.string(), md.str());
  fs::remove_all(ctx.work_dir);
  std::cout << "wrote " << out.string() << " and its " << svg_names.size() << " plots in " << perf::fmt("%.0f", took_s) << " s\n";
  return 0;
}

}  // namespace skidsim::report
