#include "apps/perf_report.h"

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

#include "apps/pour_job.h"
#include "apps/push_job.h"
#include "io/atomic_file.h"

namespace skidsim::apps {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Rung {
  std::string label;  // the cell size
  double cost = 0.0;  // wall seconds per simulated second
  double error = 0.0;
  std::string detail;
};

json read_summary(const fs::path& dir) {
  std::ifstream in(dir / "summary.json");
  if (!in) throw std::runtime_error("performance report: no summary in " + dir.string());
  return json::parse(in);
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// Error against cost on log-log axes, each rung labelled.
std::string svg_plot(const std::string& title, const std::string& error_label, const std::vector<Rung>& rungs) {
  constexpr double W = 560, H = 340, L = 70, R = 20, T = 30, B = 50;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const Rung& r : rungs) {
    const double x = std::log10(std::max(r.cost, 1e-6)), y = std::log10(std::max(r.error, 1e-6));
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  x0 = std::floor(x0), x1 = std::max(std::ceil(x1), x0 + 1), y0 = std::floor(y0), y1 = std::max(std::ceil(y1), y0 + 1);
  const auto px = [&](double c) { return L + (W - L - R) * (std::log10(std::max(c, 1e-6)) - x0) / (x1 - x0); };
  const auto py = [&](double e) { return H - B - (H - T - B) * (std::log10(std::max(e, 1e-6)) - y0) / (y1 - y0); };
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" font-family=\"sans-serif\" font-size=\"11\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << L << "\" y=\"18\" font-size=\"13\">" << title << "</text>\n"
    << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << W - L - R << "\" height=\"" << H - T - B
    << "\" fill=\"none\" stroke=\"#888\"/>\n";
  for (double d = x0; d <= x1 + 1e-9; d += 1.0)
    s << "<text x=\"" << L + (W - L - R) * (d - x0) / (x1 - x0) << "\" y=\"" << H - B + 14 << "\" text-anchor=\"middle\">1e"
      << static_cast<int>(d) << "</text>\n";
  for (double d = y0; d <= y1 + 1e-9; d += 1.0)
    s << "<text x=\"" << L - 6 << "\" y=\"" << H - B - (H - T - B) * (d - y0) / (y1 - y0) + 4 << "\" text-anchor=\"end\">1e"
      << static_cast<int>(d) << "</text>\n";
  s << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 12 << "\" text-anchor=\"middle\">cost: wall s per simulated s (one core)</text>\n"
    << "<text x=\"14\" y=\"" << (T + H - B) / 2 << "\" transform=\"rotate(-90 14 " << (T + H - B) / 2
    << ")\" text-anchor=\"middle\">" << error_label << "</text>\n<polyline fill=\"none\" stroke=\"#1f5fa8\" points=\"";
  for (const Rung& r : rungs) s << px(r.cost) << "," << py(r.error) << " ";
  s << "\"/>\n";
  for (const Rung& r : rungs)
    s << "<circle cx=\"" << px(r.cost) << "\" cy=\"" << py(r.error) << "\" r=\"4\" fill=\"#1f5fa8\"/><text x=\"" << px(r.cost) + 6
      << "\" y=\"" << py(r.error) - 6 << "\">" << r.label << "</text>\n";
  s << "</svg>\n";
  return s.str();
}

std::string table(const std::vector<Rung>& rungs, const std::string& error_header) {
  std::string t = "| cells | " + error_header + " | cost (wall s per simulated s) | |\n|---|---|---|---|\n";
  for (const Rung& r : rungs) t += "| " + r.label + " | " + fmt("%.4g", r.error) + " | " + fmt("%.4g", r.cost) + " | " + r.detail + " |\n";
  return t;
}

}  // namespace

int write_perf_report(const PerfReportJob& job) {
  const fs::path out = job.out_path;
  const fs::path work = fs::temp_directory_path() / ("skidsim_perf_" + std::to_string(::getpid()));
  fs::create_directories(work);
  const auto started = std::chrono::steady_clock::now();

  // 1. The repose cone: 600 kg poured at a point on a 6 m yard settles to a
  // cone whose flank is the stop angle alpha_I (thesis 7.1), round.
  std::vector<Rung> slope, roundness;
  double alpha_i = 30.0;
  const std::vector<double> cells = job.quick ? std::vector<double>{0.2, 0.1} : std::vector<double>{0.2, 0.1, 0.05, 0.025};
  for (const double c : cells) {
    PourJob p;
    p.cell_size_m = c;
    p.site_size_m = 6.0;
    p.pour_rate_kg_per_s = 100.0;
    p.pour_duration_s = 6.0;
    p.out_dir = (work / ("pour_" + fmt("%g", c))).string();
    if (run_pour_job(p) != 0) throw std::runtime_error("performance report: the pour at " + fmt("%g", c) + " m failed");
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
  }

  // 2. The blade push (thesis fig. 7.12): the resistance after 2 m against
  // the finest rung's.
  std::vector<Rung> push;
  const std::vector<double> densities = job.quick ? std::vector<double>{5, 10, 20} : std::vector<double>{5, 10, 20, 30, 50};
  std::vector<std::pair<double, double>> resistance;  // cells/m, N
  std::vector<double> push_cost;
  for (const double d : densities) {
    PushJob p;
    p.cells_per_m = d;
    p.distance_m = 2.0;
    p.out_dir = (work / ("push_" + fmt("%g", d))).string();
    if (run_push_job(p) != 0) throw std::runtime_error("performance report: the push at " + fmt("%g", d) + " cells/m failed");
    const json s = read_summary(p.out_dir);
    resistance.emplace_back(d, s["result"]["resistance_at_end_N"].get<double>());
    push_cost.push_back(s["performance"]["us_per_step"].get<double>() * 1e-6 / 0.002);
  }
  const double reference_N = resistance.back().second;
  for (std::size_t k = 0; k + 1 < resistance.size(); ++k)
    push.push_back({fmt("%g/m", resistance[k].first), push_cost[k], 100.0 * std::abs(resistance[k].second - reference_N) / reference_N,
                    fmt("%.0f N", resistance[k].second)});

  // The page and its plots.
  const std::string stem = out.stem().string();
  const fs::path folder = out.has_parent_path() ? out.parent_path() : fs::path(".");
  fs::create_directories(folder);
  const std::string svg_slope = stem + "_repose_slope.svg", svg_round = stem + "_repose_roundness.svg", svg_push = stem + "_push.svg";
  io::write_text_atomically((folder / svg_slope).string(), svg_plot("Repose cone: flank against alpha_I", "error (deg)", slope));
  io::write_text_atomically((folder / svg_round).string(), svg_plot("Repose cone: roundness", "diagonal vs axis radius (%)", roundness));
  io::write_text_atomically((folder / svg_push).string(),
                            svg_plot("Blade push: resistance after 2 m", "error against " + fmt("%g", densities.back()) + " cells/m (%)", push));
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  const double took_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::ostringstream md;
  md << "# Speed against error\n\n"
     << "Generated by `build/skidsim bench report" << (job.quick ? " --quick" : "") << "` on " << date << ", on a machine with "
     << std::thread::hardware_concurrency() << " cores (one used), in " << fmt("%.0f", took_s)
     << " s; every number below comes from that run. Regenerate it the same way; the figures move by up to 30 % between runs "
        "on a shared machine (compare within one page).\n\n"
     << "Cost is wall-clock seconds per simulated second on one core (below 1: faster than real time). Pick the cheapest "
        "cells that meet the error you need.\n\n"
     << "## Repose cone\n\n600 kg of dry sand poured at a point (100 kg/s for 6 s) on a 6 m yard, run until at rest. "
        "Reference: the flank settles at the stop angle alpha_I = "
     << fmt("%g", alpha_i) << " deg (thesis 4.5, 7.1); a round cone has equal radii along the axes and the diagonals.\n\n"
     << table(slope, "flank error (deg)") << "\n![flank error against cost](" << svg_slope << ")\n\n"
     << table(roundness, "roundness error (%)") << "\n![roundness against cost](" << svg_round << ")\n\n"
     << "Reading it: the roundness error falls as the cells shrink (the automaton's four-neighbour flow makes a coarse cone "
        "square; finer cells round it). The flank error reaches its floor, a few hundredths of a degree, by about 10 cm: the "
        "flank is measured over the cells between apex and foot, and below that the error is the slope's quantisation, not "
        "the model, so it wanders instead of falling further.\n\n"
     << "## Blade push\n\nA 1 m blade 0.2 m deep pushed 2 m at 1 m/s through 0.4 m of dry sand (thesis fig. 7.12; `skidsim push`). "
        "There is no closed form once soil piles up in front, so the reference is the finest rung, "
     << fmt("%g", densities.back()) << " cells/m: " << fmt("%.0f", reference_N) << " N.\n\n"
     << table(push, "resistance error (%)") << "\n![resistance error against cost](" << svg_push << ")\n\n"
     << "Reading it: the coarse rungs are far off (the blade's 0.2 m is one or two cells deep: the pile in front is "
        "blocky); from 20 cells/m the resistance is within a few per cent of the finest, and the remaining wiggle "
        "comes from where the blade's edge falls between cell rows, so it need not fall monotonically.\n\n"
     << "## Not in this page yet\n\n"
     << "BCRE diffusion, plate and wheel sinkage and the pressure under a pile have their references checked by the tests "
        "(README, Evidence) but no ladder here yet; the thesis's tables 7.1, 7.4, 7.5 and 9.3 side by side, and whole-session "
        "real-time factors, are in the README's Speed section (from `skidsim bench`).\n";
  io::write_text_atomically(out.string(), md.str());
  fs::remove_all(work);
  std::cout << "wrote " << out.string() << " and its plots (" << svg_slope << ", " << svg_round << ", " << svg_push << ") in "
            << fmt("%.0f", took_s) << " s\n";
  return 0;
}

}  // namespace skidsim::apps
