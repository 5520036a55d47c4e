// Wheels against the DEM reference (dem/wheel, scripts/dem_reference.sh): the
// lab-scale LIGGGHTS wheel runs in dimensionless form, z / D, DP / W and
// T / (W r) against slip, beside the Wong-Reece closed form and skidsim's
// wheel on the grid (report/dem_wheels.h) in the calibrated `dem_sand`, with
// the cells as many per wheel diameter as the loader's tyre has in sessions
// at 10 and 5 cm (and finer), and the cost of each rung.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "io/soil_table.h"
#include "report/dem_wheels.h"
#include "report/perf_report_parts.h"

namespace skidsim::report::perf {

namespace fs = std::filesystem;

namespace {

struct Dimensionless {
  double z = 0.0, dp = 0.0, t = 0.0;  // z / D, DP / W, T / (W r)
};

Dimensionless of(const DemWheel& w, double sinkage_m, double pull_N, double torque_Nm) {
  return {sinkage_m / (2.0 * w.radius_m), pull_N / w.load_N, torque_Nm / (w.load_N * w.radius_m)};
}

std::string triple(const Dimensionless& d) { return fmt("%.3f", d.z) + " / " + fmt("%+.2f", d.dp) + " / " + fmt("%+.2f", d.t); }

}  // namespace

// The error of a wheel against the DEM: the worst of the sinkage's relative
// error and the pull's and torque's, each relative to the DEM's value but
// not to less than a tenth of the load's scale (W, W r): near zero pull a
// relative error means nothing.
double wheel_error_against_dem(const DemWheel& dem, double sinkage_m, double pull_N, double torque_Nm) {
  const double e_z = std::abs(sinkage_m / dem.sinkage_m - 1.0);
  const double e_dp = std::abs(pull_N - dem.drawbar_pull_N) / std::max(std::abs(dem.drawbar_pull_N), 0.1 * dem.load_N);
  const double e_t = dem.towed ? std::abs(torque_Nm - dem.torque_Nm) / (0.1 * dem.load_N * dem.radius_m)
                               : std::abs(torque_Nm - dem.torque_Nm) /
                                     std::max(std::abs(dem.torque_Nm), 0.1 * dem.load_N * dem.radius_m);
  return std::max({e_z, e_dp, e_t});
}

ReportSection wheels_dem_section(const ReportContext& ctx) {
  const std::vector<DemWheel> runs = read_dem_wheels(repository_dem_dir() / "wheel" / "results");
  const io::SoilRecord soil = io::load_soil_table(io::default_soil_table_path()).at("dem_sand");
  const std::vector<double> ladder = ctx.quick ? std::vector<double>{kSessionCellsPerDiameter10cm}
                                               : std::vector<double>{kSessionCellsPerDiameter10cm,
                                                                     kSessionCellsPerDiameter5cm, 32.8};
  Curve z_dem{"DEM", {}}, dp_dem{"DEM", {}}, t_dem{"DEM", {}};
  Curve z_ref{"Wong-Reece (closed form)", {}}, dp_ref{"Wong-Reece (closed form)", {}}, t_ref{"Wong-Reece (closed form)", {}};
  std::vector<Curve> z_sk, dp_sk, t_sk;
  std::vector<Rung> rungs;
  std::vector<std::string> rows(runs.size());
  double worst_reference = 0.0;
  for (size_t k = 0; k < runs.size(); ++k) {
    const DemWheel& w = runs[k];
    const Dimensionless d = of(w, w.sinkage_m, w.drawbar_pull_N, w.torque_Nm);
    z_dem.points.emplace_back(w.slip, d.z), dp_dem.points.emplace_back(w.slip, d.dp), t_dem.points.emplace_back(w.slip, d.t);
    const WheelReference ref = closed_form_like(w, soil.terramechanics);
    const Dimensionless r = of(w, ref.sinkage_m, ref.drawbar_pull_N, ref.torque_Nm);
    worst_reference = std::max(worst_reference, wheel_error_against_dem(w, ref.sinkage_m, ref.drawbar_pull_N, ref.torque_Nm));
    rows[k] = "| " + (w.towed ? "towed, " + fmt("%+.3f", w.slip) : fmt("%+.2f", w.slip)) + " | " + triple(d) + " (" +
              fmt("%.3f", w.sinkage_sd_m / (2.0 * w.radius_m)) + " / " + fmt("%.2f", w.drawbar_pull_sd_N / w.load_N) +
              " / " + fmt("%.2f", w.torque_sd_Nm / (w.load_N * w.radius_m)) + ") | " + triple(r) + " |";
  }
  if (!runs.empty()) {
    const DemWheel& w = runs.front();
    for (double s = -0.4; s <= 0.7 + 1e-9; s += 0.05) {
      DemWheel at = w;
      at.towed = false;
      at.slip = s;
      const WheelReference ref = closed_form_like(at, soil.terramechanics);
      const Dimensionless r = of(w, ref.sinkage_m, ref.drawbar_pull_N, ref.torque_Nm);
      z_ref.points.emplace_back(s, r.z), dp_ref.points.emplace_back(s, r.dp), t_ref.points.emplace_back(s, r.t);
    }
  }
  for (const double cells : ladder) {
    Curve zc{fmt("skidsim %.1f cells/D", cells), {}, true}, dpc = zc, tc = zc;
    double wall = 0.0, simulated = 0.0, worst = 0.0;
    double worst_z = 0.0, worst_driven_dp = 0.0, worst_driven_t = 1.0, braked_t = 1.0;  // the detail column
    for (size_t k = 0; k < runs.size(); ++k) {
      const DemWheel& w = runs[k];
      const WheelLike s = wheel_like(w, soil.terramechanics, soil.flow, cells);
      wall += s.cost * s.run.simulated_s;
      simulated += s.run.simulated_s;
      const Dimensionless d = of(w, s.run.sinkage_m, s.run.drawbar_pull_N, s.run.drive_torque_Nm);
      zc.points.emplace_back(s.run.slip, d.z), dpc.points.emplace_back(s.run.slip, d.dp), tc.points.emplace_back(s.run.slip, d.t);
      worst = std::max(worst, wheel_error_against_dem(w, s.run.sinkage_m, s.run.drawbar_pull_N, s.run.drive_torque_Nm));
      worst_z = std::max(worst_z, std::abs(s.run.sinkage_m / w.sinkage_m - 1.0));
      if (!w.towed && w.slip > 0.0) {
        worst_driven_dp = std::max(worst_driven_dp, std::abs(s.run.drawbar_pull_N - w.drawbar_pull_N) / w.load_N);
        worst_driven_t = std::max(worst_driven_t, s.run.drive_torque_Nm / w.torque_Nm);
      } else if (!w.towed) {
        braked_t = std::max(braked_t, s.run.drive_torque_Nm / w.torque_Nm);
      }
      rows[k] += " " + triple(d) + " |";
    }
    z_sk.push_back(zc), dp_sk.push_back(dpc), t_sk.push_back(tc);
    rungs.push_back({fmt("%.1f cells/D", cells) + fmt(" (%.1f cm)", 100.0 * 2.0 * runs.front().radius_m / cells),
                     wall / simulated, 100.0 * worst,
                     "sinkage " + fmt("%+.0f %%", 100.0 * worst_z) + ", driven pull " + fmt("%.2f W", worst_driven_dp) +
                         " off, driven torque " + fmt("x%.2f", worst_driven_t) + ", braked torque " + fmt("x%.1f", braked_t)});
  }
  std::vector<Curve> z_curves{z_dem, z_ref}, dp_curves{dp_dem, dp_ref}, t_curves{t_dem, t_ref};
  z_curves.insert(z_curves.end(), z_sk.begin(), z_sk.end());
  dp_curves.insert(dp_curves.end(), dp_sk.begin(), dp_sk.end());
  t_curves.insert(t_curves.end(), t_sk.begin(), t_sk.end());

  ReportSection out;
  const WheelPlotNames plots = add_wheel_plots(ctx, "wheel_dem", "Wheel against the DEM: worst error over the runs",
                                               rungs, dp_curves, t_curves, z_curves, out);
  const std::string &svg_err = plots.error, &svg_dp = plots.pull, &svg_t = plots.torque, &svg_z = plots.sinkage;
  std::string header = "| slip | DEM (scatter) | Wong-Reece closed form |", rule = "|---|---|---|";
  for (const double cells : ladder) header += fmt(" skidsim, %.1f cells/D |", cells), rule += "---|";
  std::string table_rows;
  for (const std::string& r : rows) table_rows += r + "\n";
  const DemWheel* w = runs.empty() ? nullptr : &runs.front();
  double mean_load_N = 0.0;
  for (const DemWheel& r : runs) mean_load_N += r.load_N / static_cast<double>(runs.size());
  out.markdown =
      "## Wheels against the DEM reference\n\n"
      "The LIGGGHTS wheel runs of `dem/wheel/` (a rigid wheel " +
      (w ? fmt("%.2f m", 2.0 * w->radius_m) + " across and " + fmt("%.2f m", w->width_m) + " wide carrying " +
               fmt("%.0f N", mean_load_N) + " on " + fmt("%.3f m", w->bed_depth_m) + " of the 8 mm grains, rough rim, moved at " +
               fmt("%.2f m/s", w->speed_m_s)
         : std::string("(no runs)")) +
      "; towed free to spin, driven or braked at a held slip; means over the steady travel, `dem/README.md`) against "
      "skidsim's wheel on the grid in `dem_sand`, whose Bekker, unloading and Janosi parameters come from the DEM's "
      "plate and shear-box tests alone, and the Wong-Reece closed form in the same soil. Each cell: z / D, DP / W, "
      "T / (W r); the DEM's scatter is the standard deviation of its 7.5 ms means. skidsim runs the lab wheel with as "
      "many cells per diameter as the loader's 0.82 m tyre has at 10 and 5 cm (8.2 and 16.4). Error: the worst over "
      "the runs of the sinkage's, the pull's and the torque's, each relative to the DEM's but not to less than a tenth "
      "of W (W r); the closed form's own is " + fmt("%.0f %%", 100.0 * worst_reference) + ".\n\n" + header + "\n" + rule +
      "\n" + table_rows + "\n" + table(rungs, "worst error against the DEM (%)", kCostPerSimulatedSecond, "cells per wheel diameter") +
      "\n![error against cost](" + svg_err + ")\n![pull against slip](" + svg_dp + ")\n![torque against slip](" + svg_t +
      ")\n![sinkage against slip](" + svg_z + ")\n\n"
      "Reading it: skidsim is the theory at every rung (the grid only supplies the soil ahead), so its error against "
      "the DEM is the theory's and no finer cell removes it. The theory meets the DEM's towed rolling resistance and "
      "its growth of sinkage with slip to 0.2 (Lyasko), but sinks the wheel about a third deeper, pulls and turns "
      "harder when driven and far harder when braked; docs/soil_contact.md (\"Wheels against the DEM reference\") "
      "says why and what is left. The issue's 20 % is not reached.\n\n";
  return out;
}

}  // namespace skidsim::report::perf
