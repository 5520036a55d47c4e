// Speed against error for wheels on soft soil (docs/soil_contact.md,
// "Wheels"): the Wong-Reece wheel rolling on the grid (experiments/
// loading_experiments.h run_soft_wheel, as tests/terrain_soft_wheel_test.cpp
// runs it) against the closed form evaluated apart (experiments/
// wong_reece_closed_form.h), towed and driven, over cell sizes; the pull-,
// torque- and sinkage-slip curves beside it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "experiments/loading_experiments.h"
#include "experiments/wong_reece_closed_form.h"
#include "report/perf_report_parts.h"
#include "terrain/granular_grid.h"
#include "terrain/soil_mechanics.h"

namespace skidsim::report::perf {
namespace {

using terrain::kGravity_m_s2;

constexpr double kStepS = 0.002, kSoilDepthM = 0.5;
constexpr double kRadiusM = 0.3, kWidthM = 0.3, kMassKg = 300.0;  // the terrain test's wheel
constexpr double kSpeedMps = 0.5, kTravelM = 1.6;

struct SlipRun {
  double slip = 0.0;  // asked (NaN: towed)
  terrain::SoftWheelRun run;
  double wall_s = 0.0;
};

SlipRun run_at(double cells_per_m, double slip) {
  terrain::GridSpec spec;
  spec.cell_size_m = 1.0 / cells_per_m;
  spec.nx = static_cast<int>(std::lround(3.0 * cells_per_m));
  spec.ny = static_cast<int>(std::lround(1.6 * cells_per_m));
  terrain::GranularGrid g(spec, terrain::SoilFlowParameters{}, kStepS);
  for (int j = 0; j < spec.ny; ++j)
    for (int i = 0; i < spec.nx; ++i) g.set_material_m(i, j, kSoilDepthM);
  const auto start = std::chrono::steady_clock::now();
  SlipRun r;
  r.slip = slip;
  r.run = terrain::run_soft_wheel(g, terrain::SoilMechanics{}, kMassKg, kRadiusM, kWidthM, slip, kSpeedMps, kTravelM,
                                  kSoilDepthM, kStepS);
  r.wall_s = seconds_since(start);
  return r;
}

struct Reference {
  double slip = 0.0, z = 0.0, dp = 0.0, t = 0.0;
};

Reference reference_at(const closed_form::WongReeceSoil& soil, double load_N, double slip) {
  Reference r;
  r.slip = slip;
  r.z = closed_form::wong_reece_reference_sinkage(soil, kRadiusM, kWidthM, load_N, slip);
  const closed_form::WongReeceResult f = closed_form::wong_reece_reference(soil, kRadiusM, kWidthM, r.z, slip);
  r.dp = f.DP;
  r.t = f.T;
  return r;
}

std::string cell_label(double cells_per_m) { return fmt("%g cm", 100.0 / cells_per_m); }

}  // namespace

WheelPlotNames add_wheel_plots(const ReportContext& ctx, const std::string& prefix, const std::string& error_title,
                               const std::vector<Rung>& rungs, const std::vector<Curve>& pull,
                               const std::vector<Curve>& torque, const std::vector<Curve>& sinkage, ReportSection& s) {
  const WheelPlotNames n{ctx.svg_name(prefix + "_error"), ctx.svg_name(prefix + "_pull"), ctx.svg_name(prefix + "_torque"),
                         ctx.svg_name(prefix + "_sinkage")};
  s.svgs.emplace_back(n.error, svg_plot(error_title, "worst error (%)", rungs));
  s.svgs.emplace_back(n.pull, svg_curves("Drawbar pull against slip", "slip", "DP / W", pull));
  s.svgs.emplace_back(n.torque, svg_curves("Torque against slip", "slip", "T / (W r)", torque));
  s.svgs.emplace_back(n.sinkage, svg_curves("Sinkage against slip", "slip", "z / D", sinkage));
  return n;
}

ReportSection soft_wheel_section(const ReportContext& ctx) {
  const std::vector<double> ladder = ctx.quick ? std::vector<double>{10, 20} : std::vector<double>{5, 10, 20, 40, 80};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> slips = {nan, 0.1, 0.2, 0.4, 0.6};
  const terrain::SoilMechanics sand;
  const closed_form::WongReeceSoil soil = closed_form::reference_soil_of(sand);
  const double load_N = kMassKg * kGravity_m_s2;
  const double towed_slip = closed_form::wong_reece_reference_towed_slip(soil, kRadiusM, kWidthM, load_N);

  // The closed form's curves over slip, and at the runs' slips.
  Curve z_ref{"Wong-Reece (closed form)", {}}, dp_ref{"Wong-Reece (closed form)", {}}, t_ref{"Wong-Reece (closed form)", {}};
  for (double s = -0.3; s <= 0.8 + 1e-9; s += 0.05) {
    const Reference r = reference_at(soil, load_N, s);
    z_ref.points.emplace_back(s, r.z / (2.0 * kRadiusM));
    dp_ref.points.emplace_back(s, r.dp / load_N);
    t_ref.points.emplace_back(s, r.t / (load_N * kRadiusM));
  }
  std::vector<Curve> z_curves{z_ref}, dp_curves{dp_ref}, t_curves{t_ref};

  LadderBudget budget(kRungBudgetS);
  std::vector<double> cells_per_m;
  std::vector<Rung> rungs;
  std::string values;  // the finest rung's figures, a row per slip
  for (const double c : ladder) {
    if (!budget.allow(cell_label(c))) continue;
    cells_per_m.push_back(c);
    double wall = 0.0, simulated = 0.0, worst = 0.0;
    std::string worst_what;
    Curve zc{cell_label(c), {}}, dpc{cell_label(c), {}}, tc{cell_label(c), {}};
    std::string rows;
    for (const double slip : slips) {
      const bool towed = std::isnan(slip);
      const SlipRun r = run_at(c, slip);
      wall += r.wall_s;
      simulated += r.run.simulated_s;
      const Reference ref = reference_at(soil, load_N, towed ? towed_slip : slip);
      // Errors: sinkage and pull (and, driven, torque) against the closed
      // form at the slip asked (towed: the closed form's own towed slip).
      const double e_z = 100.0 * (r.run.sinkage_m / ref.z - 1.0);
      const double e_dp = 100.0 * (r.run.drawbar_pull_N / ref.dp - 1.0);
      const double e_t = towed ? 0.0 : 100.0 * (r.run.drive_torque_Nm / ref.t - 1.0);
      const std::string at = towed ? "towed" : fmt("s %.1f", slip);
      for (const auto& [e, what] : {std::pair{e_z, "sinkage"}, std::pair{e_dp, "pull"}, std::pair{e_t, "torque"}})
        if (std::abs(e) > worst) worst = std::abs(e), worst_what = std::string(what) + " at " + at + " " + fmt("%+.1f", e) + " %";
      zc.points.emplace_back(r.run.slip, r.run.sinkage_m / (2.0 * kRadiusM));
      dpc.points.emplace_back(r.run.slip, r.run.drawbar_pull_N / load_N);
      tc.points.emplace_back(r.run.slip, r.run.drive_torque_Nm / (load_N * kRadiusM));
      rows += "| " + (towed ? "towed (" + fmt("%.3f", r.run.slip) + ")" : fmt("%.1f", slip)) + " | " +
              fmt("%.4f", r.run.sinkage_m) + " (" + fmt("%.4f", ref.z) + ", " + fmt("%+.1f", e_z) + " %) | " +
              fmt("%+.0f", r.run.drawbar_pull_N) + " (" + fmt("%+.0f", ref.dp) + ", " + fmt("%+.1f", e_dp) + " %) | " +
              fmt("%+.0f", r.run.drive_torque_Nm) + " (" + fmt("%+.0f", ref.t) + (towed ? "" : ", " + fmt("%+.1f", e_t) + " %") + ") |\n";
    }
    budget.ran(wall);
    rungs.push_back({cell_label(c), wall / simulated, worst, "worst: " + worst_what});
    z_curves.push_back(zc), dp_curves.push_back(dpc), t_curves.push_back(tc);
    values = "| slip | sinkage, m (closed form, error) | pull, N (closed form, error) | torque, N m (closed form, error) |\n"
             "|---|---|---|---|\n" + rows;
  }
  std::vector<double> sizes;
  for (const double c : cells_per_m) sizes.push_back(1.0 / c);
  const Convergence conv = convergence(sizes, rungs, "wheel's worst error");
  // Past its largest the error may fall at every rung: say so, with the numbers.
  std::string past_largest;
  if (rungs.size() >= 3) {
    size_t top = 0;
    for (size_t k = 1; k < rungs.size(); ++k)
      if (rungs[k].error > rungs[top].error) top = k;
    bool falls = top + 1 < rungs.size();
    for (size_t k = top + 1; k < rungs.size(); ++k) falls = falls && rungs[k].error < rungs[k - 1].error;
    if (falls)
      past_largest = " Past its largest, " + fmt("%.2g %%", rungs[top].error) + " at " + rungs[top].label +
                     ", it falls at every rung, to " + fmt("%.2g %%", rungs.back().error) + " at " + rungs.back().label +
                     ": it does not grow as the cells shrink further.";
  }

  ReportSection s;
  const WheelPlotNames plots = add_wheel_plots(ctx, "wheel", "Wong-Reece wheel on the grid against its closed form",
                                               rungs, dp_curves, t_curves, z_curves, s);
  const std::string &svg_err = plots.error, &svg_dp = plots.pull, &svg_t = plots.torque, &svg_z = plots.sinkage;
  s.markdown =
      "## Wheels on soft soil\n\nA rigid wheel 0.6 m across and 0.3 m wide carrying " + fmt("%.0f", kMassKg) +
      " kg on 0.5 m of dry sand (Wong's LLL sand), rolled " + fmt("%.1f", kTravelM) + " m at " + fmt("%.1f", kSpeedMps) +
      " m/s on the grid (experiments/loading_experiments.h run_soft_wheel, as tests/terrain_soft_wheel_test.cpp runs "
      "it): towed (free to spin) and driven at slips 0.1, 0.2, 0.4 and 0.6, free to sink. Reference: the Wong-Reece "
      "wheel's closed form (experiments/wong_reece_closed_form.h, the published integrals evaluated apart from the model; "
      "towed, it skids at s = " + fmt("%.3f", towed_slip) + "). Error: the worst of sinkage, pull and torque over the five "
      "runs (the towed wheel's torque is zero by construction). Cost: wall s per simulated s over the five runs.\n\n" +
      table(rungs, "worst error (%)") + "\n![wheel error against cost](" + svg_err + ")\n\nReading it: " + conv.reading + past_largest +
      "\n\nAt the finest rung run (" + (cells_per_m.empty() ? std::string("none") : cell_label(cells_per_m.back())) +
      "):\n\n" + values + "\n![pull against slip](" + svg_dp + ")\n![torque against slip](" + svg_t +
      ")\n![sinkage against slip](" + svg_z + ")\n\n";
  s.markdown += sentence(budget.skipped_note()) + "\n\n";
  return s;
}

}  // namespace skidsim::report::perf
