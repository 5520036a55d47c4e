// Speed against error for the automaton's own references (docs/validation.md,
// cases 3 and 6): the BCRE diffusion of a bump on a flowing slope, over cell
// sizes and over the avalanche sweep's sub-steps, and the load a settled
// pile puts on its base. Each case is set up as its test sets it up
// (tests/terrain_bcre_test.cpp, tests/terrain_load_spreading_test.cpp), so
// the page's errors are the ones the tests bound.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "report/perf_report_parts.h"
#include "common/physical_constants.h"
#include "experiments/bcre_bump.h"
#include "terrain/granular_grid.h"
#include "terrain/load_spreading.h"

namespace skidsim::report::perf {
namespace {

using terrain::GranularGrid;
using terrain::GridSpec;
using terrain::SoilFlowParameters;

constexpr double kStepS = 0.002;  // the engine's step (engine::kStepSeconds)

std::string cell_label(double cell_m) { return fmt("%g cm", 100.0 * cell_m); }

// --- BCRE consistency (thesis 4.4.2) ---------------------------------------
//
// The strip of experiments/bcre_bump.h (a Gaussian bump diffusing on a 55 deg
// slope, against the diffusion's closed form), run for 0.02 s.
struct BumpRun {
  double error = 0.0;
  double cost = 0.0;  // wall s per simulated s, the steps alone
  int substeps = 0;
  double z_plus_over_cell = 0.0;  // per sweep: r = D dt_sweep / d^2
  double sweep_dt_s = 0.0;
};

constexpr double kBumpEndS = 0.02;

BumpRun diffusing_bump(double cell_m, double bound_fraction, double timing_wall_s) {
  const long steps = std::lround(kBumpEndS / kStepS);
  BumpRun out;
  double timed_s = 0.0;
  int runs = 0;
  // The same run again until the steps have taken `timing_wall_s` of wall
  // time (at least once): the cost of exactly the run that was measured.
  do {
    GranularGrid g = terrain::bcre_bump_strip(cell_m, kStepS, bound_fraction);
    const auto start = std::chrono::steady_clock::now();
    for (long s = 0; s < steps; ++s) g.step();
    timed_s += seconds_since(start);
    ++runs;
    if (runs == 1) {
      out.error = terrain::bcre_bump_error(g, static_cast<double>(steps) * kStepS);
      out.substeps = g.flow_law().substeps;
      out.z_plus_over_cell = g.flow_law().z_plus_per_sweep_m / cell_m;
      out.sweep_dt_s = g.flow_law().sweep_dt_s;
    }
  } while (timed_s < timing_wall_s);
  out.cost = timed_s / (runs * static_cast<double>(steps) * kStepS);
  return out;
}

}  // namespace

ReportSection bcre_section(const ReportContext& ctx) {
  const double timing_s = ctx.quick ? 0.005 : 0.2;
  // Cells: the report's ladder, and in the full run the test's two finer
  // rungs (the bump is 0.1 m wide: the coarse rungs hardly resolve it).
  const std::vector<double> ladder = ctx.quick ? std::vector<double>{0.05, 0.025}
                                               : std::vector<double>{0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125};
  std::vector<double> cells;  // the rungs run
  std::vector<Rung> by_cell;
  LadderBudget budget(kRungBudgetS);
  for (const double d : ladder) {
    if (!budget.allow(cell_label(d))) continue;
    const auto started = std::chrono::steady_clock::now();
    const BumpRun r = diffusing_bump(d, 1.0, timing_s);
    budget.ran(seconds_since(started));
    cells.push_back(d);
    by_cell.push_back({cell_label(d), r.cost, 100.0 * r.error,
                       fmt("%.0f", r.substeps) + " sweeps per 2 ms step (z+/d = " + fmt("%.3f", r.z_plus_over_cell) + " per sweep); sigma0 = " +
                           fmt("%.1f", terrain::kBcreBumpSigma0M / d) + " cells"});
  }
  const Convergence cc = convergence(cells, by_cell, "error against the diffusion");

  // Sub-steps at one cell size: the flow law's bound fraction below 1 makes
  // the sweep sub-step more (GridSpec::flow_bound_fraction).
  const double sub_cell = 0.025;
  const std::vector<double> fractions = ctx.quick ? std::vector<double>{1.0, 0.5} : std::vector<double>{1.0, 0.5, 0.25, 0.125};
  std::vector<Rung> by_substeps;
  std::vector<double> sweep_dt, coefficient;  // coefficient: abs(1/12 - r/2) per rung
  for (const double f : fractions) {
    const BumpRun r = diffusing_bump(sub_cell, f, timing_s);
    // The explicit sweep's modified equation: its leading error is
    // D d^2 u'''' (1/12 - r/2) with r = D dt_sweep / d^2 (the space error
    // 1/12 of the three-point Laplacian, the time error -r/2 of the forward
    // step), so more sub-steps (smaller r) need not mean a smaller error.
    by_substeps.push_back({fmt("%.0f sweeps", r.substeps), r.cost, 100.0 * r.error,
                           "r = z+/d = " + fmt("%.3f", r.z_plus_over_cell) + " per sweep; leading-error coefficient abs(1/12 - r/2) = " +
                               fmt("%.4f", std::abs(1.0 / 12.0 - 0.5 * r.z_plus_over_cell))});
    sweep_dt.push_back(r.sweep_dt_s);
    coefficient.push_back(std::abs(1.0 / 12.0 - 0.5 * r.z_plus_over_cell));
  }
  const Convergence cs = convergence(sweep_dt, by_substeps, "error against the diffusion", "sweep time steps");

  ReportSection s;
  const std::string svg_cells = ctx.svg_name("bcre_cells"), svg_sub = ctx.svg_name("bcre_substeps");
  s.svgs.emplace_back(svg_cells, svg_plot("BCRE diffusion of a bump: cell size", "largest error (% of the bump)", by_cell));
  s.svgs.emplace_back(svg_sub, svg_plot("BCRE diffusion at " + cell_label(sub_cell) + ": sweeps per step",
                                        "largest error (% of the bump)", by_substeps));
  s.markdown = "## BCRE diffusion\n\nA 2 m strip of dry sand, one row of cells, inclined at 55 deg (every cell flowing) and carrying a "
               "Gaussian bump 2 cm high, sigma0 = 0.1 m wide, run for 0.02 s (tests/terrain_bcre_test.cpp). Reference: in the flowing "
               "regime the automaton discretises the BCRE diffusion dh/dt = v h_r lap(h) (thesis 4.4.2), whose solution is the bump "
               "widened to sigma^2 = sigma0^2 + 2 v h_r t. Error: the largest difference over the middle metre, in % of the bump's "
               "height. Cost: the strip's steps, wall s per simulated s (one row of cells: a 2-D area costs (2 m / d) times "
               "more).\n\n" +
               table(by_cell, "largest error (% of the bump)") + "\n![BCRE error against cost, by cell size](" + svg_cells + ")\n\n" +
               "Reading it: " + cc.reading;
  if (cc.trend == Trend::kFalls || cc.trend == Trend::kFallsOverall) {
    s.markdown += " The three-point Laplacian is second order in d once the sweep sub-steps at its bound (z+/d per sweep "
                  "fixed, so dt_sweep ~ d^2): compare the orders rung to rung with 2.";
    // The coarsest rung whose order falls well short of 2: how many cells
    // sigma0 spans there.
    for (std::size_t k = 0; k < cc.orders.size(); ++k)
      if (cc.orders[k] < 1.5) {
        s.markdown += " Short of it from " + by_cell[k].label + " to " + by_cell[k + 1].label + ", where sigma0 spans " +
                      fmt("%.1f", terrain::kBcreBumpSigma0M / cells[k]) + " to " + fmt("%.1f", terrain::kBcreBumpSigma0M / cells[k + 1]) +
                      " cells: the bump is not yet resolved there.";
        break;
      }
  }
  else
    s.markdown += " The bump is " + fmt("%.1f", terrain::kBcreBumpSigma0M / cells.back()) +
                  " cells wide at the finest rung, so it is resolved: an error that does not fall with the cells is not the "
                  "Laplacian's (compare the sub-steps below).";
  if (cells.back() < 0.0125)
    s.markdown += " (The ladder goes on past 1.25 cm to the test's finer rungs: one row of cells keeps them cheap.)";
  s.markdown += sentence(budget.skipped_note());
  s.markdown += "\n\nSub-steps: at " + cell_label(sub_cell) + " the stability bound (z+/d <= 1/4 per sweep) already splits a 2 ms step into " +
                by_substeps.front().label + "; a smaller share of the bound (GridSpec::flow_bound_fraction) splits it further.\n\n" +
                table(by_substeps, "largest error (% of the bump)", kCostPerSimulatedSecond, "sweeps per step") +
                "\n![BCRE error against cost, by sub-steps](" + svg_sub + ")\n\nReading it: " + cs.reading;
  // Do the measured errors rank as the modified equation's coefficient does?
  bool follows = true;
  std::size_t best = 0;
  for (std::size_t i = 0; i < by_substeps.size(); ++i) {
    if (by_substeps[i].error < by_substeps[best].error) best = i;
    for (std::size_t j = i + 1; j < by_substeps.size(); ++j)
      if ((by_substeps[i].error < by_substeps[j].error) != (coefficient[i] < coefficient[j])) follows = false;
  }
  if (follows)
    s.markdown += " The errors rank as the modified equation's leading coefficient abs(1/12 - r/2) does (last column): the "
                  "forward step's time error (-r/2) cancels the Laplacian's space error (1/12) near r = 1/6, so sub-steps "
                  "beyond that cost proportionally more and make the error larger, not smaller.";
  else
    s.markdown += " The errors do not rank as the modified equation's leading coefficient abs(1/12 - r/2) does (last column): "
                  "what is left is not its leading term.";
  s.markdown += " The least error here is at " + by_substeps[best].label + ".";
  s.markdown += "\n\n";
  return s;
}

// --- The load under a pile (thesis 6.5, 7.3.3, fig. 7.13) ---------------------

namespace {

struct PileRun {
  double kink_share = 0.0;       // largest |l(i-1) - 2 l(i) + l(i+1)| along the axis, over the peak load
  double sum_error = 0.0;        // |sum of base loads - weight| / weight
  int monotone_breaks = 0;       // cells where the load rises away from the centre
  double flank_ratio = 0.0;      // flank base load over the flank's own columns (> 1: load passed outwards)
  double eval_s = 0.0;           // wall s per base_loads_N
  double settle_sim_s = 0.0, settle_wall_s = 0.0;
  int radius_cells = 0;
};

// 0.12 m^3 poured at the centre of a 3 m closed grid, 0.0004 m^3 per 2 ms
// step, then left to settle; its base loads for block heights of 1, 1.5 and
// 2 cells (the worst of the three is reported), as in the test.
PileRun pile_under(double cell_m, double timing_wall_s) {
  GridSpec spec;
  spec.nx = spec.ny = static_cast<int>(std::lround(3.0 / cell_m));
  spec.cell_size_m = cell_m;
  GranularGrid g(spec, SoilFlowParameters{}, kStepS);
  const int n = spec.nx, c = n / 2;
  PileRun out;
  const auto start = std::chrono::steady_clock::now();
  long steps = 0;
  for (double poured = 0.0; poured < 0.12; poured += 0.0004, ++steps) {
    g.add_material_m3(c, c, 0.0004);
    g.step();
  }
  for (; !g.at_rest() && steps < 400000; ++steps) g.step();
  out.settle_wall_s = seconds_since(start);
  out.settle_sim_s = static_cast<double>(steps) * kStepS;
  const double g_m_s2 = kGravity_m_s2;
  const double weight_N = static_cast<double>(g.total_quanta()) * g.quantum_mass_kg() * g_m_s2;
  while (out.radius_cells < n - 1 - c && g.material_m(c + out.radius_cells + 1, c) > 0.0) ++out.radius_cells;
  std::vector<double> loads;
  terrain::LoadSpreadingScratch scratch;
  const auto load = [&](int i, int j) { return loads[static_cast<std::size_t>(g.index(i, j))]; };
  const auto column = [&](int i, int j) { return g.material_m(i, j) * g.soil().bulk_density_kg_m3 * g_m_s2 * cell_m * cell_m; };
  for (const double block_cells : {1.0, 1.5, 2.0}) {
    terrain::LoadSpreading spreading;
    spreading.block_height_cells = block_cells;
    double timed = 0.0;
    int evaluations = 0;
    do {
      const auto t0 = std::chrono::steady_clock::now();
      terrain::base_loads_N(g, spreading, g_m_s2, &loads, &scratch);
      timed += seconds_since(t0);
      ++evaluations;
    } while (timed < timing_wall_s / 3.0);
    out.eval_s = std::max(out.eval_s, timed / evaluations);
    double sum = 0.0;
    for (const double l : loads) sum += l;
    out.sum_error = std::max(out.sum_error, std::abs(sum - weight_N) / weight_N);
    double peak = 0.0;
    for (int i = 0; i < n; ++i) peak = std::max(peak, load(i, c));
    for (int i = 1; i + 1 < n; ++i) {
      out.kink_share = std::max(out.kink_share, std::abs(load(i - 1, c) - 2.0 * load(i, c) + load(i + 1, c)) / peak);
      if (i + 1 <= c && load(i - 1, c) > load(i, c) + 1e-9 * peak) ++out.monotone_breaks;
      if (i > c && load(i + 1, c) > load(i, c) + 1e-9 * peak) ++out.monotone_breaks;
    }
    // Beyond half the pile's radius the base carries more than the columns
    // there weigh: the core passes load outwards (eps > 1/3).
    const int half = out.radius_cells / 2;
    double flank_load = 0.0, flank_columns = 0.0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        if (std::hypot(i - c, j - c) < half) continue;
        flank_load += load(i, j);
        flank_columns += column(i, j);
      }
    const double ratio = flank_columns > 0.0 ? flank_load / flank_columns : 0.0;
    out.flank_ratio = block_cells == 1.0 ? ratio : std::min(out.flank_ratio, ratio);
  }
  return out;
}

}  // namespace

ReportSection pile_load_section(const ReportContext& ctx) {
  const std::vector<double> ladder = ctx.quick ? std::vector<double>{0.2, 0.1} : std::vector<double>{0.2, 0.1, 0.05, 0.025, 0.0125};
  std::vector<double> cells;  // the rungs run
  std::vector<Rung> rungs;
  double worst_sum = 0.0, least_flank = 1e300;
  int breaks = 0;
  LadderBudget budget(kRungBudgetS);
  for (const double d : ladder) {
    if (!budget.allow(cell_label(d))) continue;
    const auto started = std::chrono::steady_clock::now();
    const PileRun p = pile_under(d, ctx.quick ? 0.002 : 0.1);
    budget.ran(seconds_since(started));
    cells.push_back(d);
    worst_sum = std::max(worst_sum, p.sum_error);
    least_flank = std::min(least_flank, p.flank_ratio);
    breaks += p.monotone_breaks;
    rungs.push_back({cell_label(d), p.eval_s, 100.0 * p.kink_share,
                     "pile radius " + fmt("%.0f", p.radius_cells) + " cells; sum of loads - weight: " + fmt("%.1e", p.sum_error) +
                         " of the weight; flank carries " + fmt("%.2f", p.flank_ratio) + "x its columns; " +
                         fmt("%.0f", p.monotone_breaks) + " rises away from the centre; settling took " + fmt("%.1f", p.settle_sim_s) +
                         " s simulated in " + fmt("%.1f", p.settle_wall_s) + " s"});
  }
  const Convergence c = convergence(cells, rungs, "largest kink");
  ReportSection s;
  const std::string svg = ctx.svg_name("pile_load");
  s.svgs.emplace_back(svg, svg_plot("Load under a pile: smoothness", "largest kink (% of the peak load)", rungs,
                                    "cost: wall s per evaluation of the base loads"));
  s.markdown =
      "## Pressure under a pile\n\n0.12 m^3 of dry sand poured at the centre of a 3 m closed yard and left to settle; the base "
      "loads from the load-spreading model (thesis 6.5, eps = 0.4, blocks 1, 1.5 and 2 cells high, the worst of the three; "
      "tests/terrain_load_spreading_test.cpp). References: the base loads sum to the pile's weight exactly, and follow the pile "
      "smoothly (fig. 7.13): the error is the largest kink along the pile's axis, |l(i-1) - 2 l(i) + l(i+1)|, in % of the peak "
      "load (the test bounds it at 10 %). Cost: wall s per evaluation of the base loads (a static case; the settling's own cost is "
      "in the last column).\n\n" +
      table(rungs, "largest kink (% of peak)", "cost (wall s per evaluation)") + "\n![kink against cost](" + svg + ")\n\n" +
      "Reading it: the loads sum to the weight to " + fmt("%.1e", worst_sum) + " (relative) at every rung; the flank carries at least " +
      fmt("%.2f", least_flank) + "x its own columns (load passed outwards); " + fmt("%.0f", breaks) +
      " places where the load rises away from the centre, over the whole ladder. " + c.reading;
  if (c.trend == Trend::kFalls || c.trend == Trend::kFallsOverall)
    s.markdown += " The apex of a repose cone is a kink in the pile itself; the spreading's blocks are a cell or two high, so "
                  "the spread narrows with the cell and an order near 1 (a kink sampled at spacing d) is what to expect.";
  else
    s.markdown += " The blocks are a fixed number of cells high, so the spreading narrows with the cells and the kink at the "
                  "cone's apex, a property of the pile rather than of the grid, is sampled ever more finely without shrinking.";
  s.markdown += sentence(budget.skipped_note()) + "\n\n";
  return s;
}

}  // namespace skidsim::report::perf
