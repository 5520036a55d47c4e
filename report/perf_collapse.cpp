// Collapsing columns against the DEM reference (dem/collapse,
// scripts/dem_reference.sh): the LIGGGHTS columns of aspect ratio 0.5-4 and
// the slot, in dimensionless form (run-out and final height over r0, the
// front against t / sqrt(H0 / g)), beside today's two ground models
// (experiments/column_collapse.h) in the calibrated `dem_sand`, the column
// scaled to r0 = 1 m so the sessions' 10 and 5 cm cells are 10 and 20 per
// radius, and the cost of each rung.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "common/physical_constants.h"
#include "experiments/column_collapse.h"
#include "experiments/fed_heap.h"
#include "io/soil_table.h"
#include "report/dem_columns.h"
#include "report/perf_report_parts.h"

namespace skidsim::report::perf {

namespace fs = std::filesystem;

namespace {

using terrain::CollapseCase;
using terrain::CollapseRun;
using terrain::GroundModel;

// The heap fed at known rates (experiments/fed_heap.h) against the DEM's:
// the slope a pour onto a heap stands at for each feed, the automaton alone
// and with the fast flow (the feed landing with its fall), at the columns'
// scale; slopes in degrees.
std::string fed_heap_table(const fs::path& dem_dir, const terrain::SoilFlowParameters& sand, const std::vector<double>& cells) {
  std::string header = "| Q (m^2/s per m) | DEM: mean [5-95 %] |", rule = "|---|---|";
  for (const char* model : {"automaton", "automaton + momentum"})
    for (double cell : cells) header += std::string(" ") + model + ", " + fmt("%g", cell * 100.0) + " cm |", rule += "---|";
  std::string rows;
  for (const DemFedHeap& d : read_dem_fed_heap(dem_dir)) {
    rows += "| " + fmt("%g", d.q_m2_s) + " | " + fmt("%.1f", slope_deg(d.tan_mean)) + " [" + fmt("%.1f", slope_deg(d.tan_p05)) +
            "-" + fmt("%.1f", slope_deg(d.tan_p95)) + "]";
    for (bool momentum : {false, true})
      for (double cell : cells)
        rows += " | " + fmt("%.1f", slope_deg(terrain::run_fed_heap(dem_fed_heap_case(d, cell, momentum), sand).tan_slope));
    rows += " |\n";
  }
  return header + "\n" + rule + "\n" + rows;
}

// Tubes at r0 = 1 m with the soils' own grains and their bed's friction on
// the floor (experiments/column_collapse.h, laboratory_column_case) against
// the published run-out law: dem_sand with the fast flow at its defaults
// (the DEM tables' model), the sessions' sands with the flow the sessions
// run (terrain::session_flow_parameters), and the automaton alone. Each
// cell: run-out / height over r0.
std::string published_laws_table(const io::SoilTable& soils, const std::vector<double>& cells) {
  const char* const names[] = {"dem_sand", "dry_sand", "lete_sand"};
  std::string header = "| a | published run-out |", rule = "|---|---|";
  auto sessions_sand = [&](const char* name) { return std::string(name) != "dem_sand"; };
  for (const char* name : names)
    for (double cell : cells)
      header += std::string(" ") + name + (sessions_sand(name) ? " (the sessions' flow)" : "") + ", " + fmt("%g", cell * 100.0) + " cm |",
          rule += "---|";
  for (const char* name : names) header += std::string(" ") + name + ", automaton alone, 10 cm |", rule += "---|";
  std::string rows;
  for (double a : {0.5, 1.0, 2.0, 4.0}) {
    rows += "| " + fmt("%g", a) + " | " + fmt("%.2f", terrain::published_runout_over_r0(a));
    auto cell_text = [&](const char* name, double cell, bool momentum) {
      CollapseCase c = terrain::laboratory_column_case(a, cell);
      c.momentum = momentum;
      if (sessions_sand(name)) c.momentum_params = terrain::session_flow_parameters();
      const CollapseRun run = terrain::run_column_collapse(c, soils.at(name).flow);
      return " | " + fmt("%.2f", run.runout_over_r0) + " / " + fmt("%.2f", run.final_height_over_r0);
    };
    for (const char* name : names)
      for (double cell : cells) rows += cell_text(name, cell, true);
    for (const char* name : names) rows += cell_text(name, 0.1, false);
    rows += " |\n";
  }
  return header + "\n" + rule + "\n" + rows;
}

// The friction side study (kFrictionStudy): the DEM's tubes and the
// model's in the calibrated material and in each other one, the model given
// each calibration (calibrated_flow). Each cell: r99 / height over r0.
std::string friction_study_table(const fs::path& dem_dir, const std::vector<DemColumn>& base,
                                 const terrain::SoilFlowParameters& sand, const std::vector<double>& cells) {
  std::string header = "| rolling friction | column | repose (deg) | DEM |", rule = "|---|---|---|---|";
  for (double cell : cells) header += " model, " + fmt("%g", cell * 100.0) + " cm |", rule += "---|";
  auto pair = [](double runout, double height) { return fmt("%.2f", runout) + " / " + fmt("%.2f", height); };
  std::string rows;
  auto add = [&](double mu_r, const std::vector<DemColumn>& dem, const terrain::SoilFlowParameters& soil) {
    for (const DemColumn& d : dem) {
      if (!standing_tube(d) || d.aspect > 2.0) continue;
      rows += "| " + fmt("%g", mu_r) + " | " + column_name(d) + " | " + fmt("%.1f", soil.repose_angle_deg) + " | " +
              pair(d.runout, d.height);
      for (double cell : cells) {
        const CollapseRun run = terrain::run_column_collapse(dem_column_case(d, cell, true, true), soil);
        rows += " | " + pair(run.runout_over_r0, run.final_height_over_r0);
      }
      rows += " |\n";
    }
  };
  add(0.3, base, sand);
  for (const FrictionStudyMaterial& m : kFrictionStudy)
    add(m.rolling_friction, read_dem_columns(dem_dir, m.results), calibrated_flow(columns_material(dem_dir, m.results), sand));
  return header + "\n" + rule + "\n" + rows;
}

}  // namespace

ReportSection collapse_dem_section(const ReportContext& ctx) {
  const fs::path dem_dir = repository_dem_dir();
  const std::vector<DemColumn> dem = read_dem_columns(dem_dir);
  if (dem.empty()) throw std::runtime_error("performance report: no DEM columns in " + dem_dir.string());
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  const io::SoilRecord dem_sand = soils.at("dem_sand");
  const terrain::SoilFlowParameters& sand = dem_sand.flow;
  const std::vector<double> cells = ctx.quick ? std::vector<double>{0.1} : std::vector<double>{0.1, 0.05};
  // Today's two ground models, and the automaton with the fast-flow
  // prototype (terrain/momentum_flow.h) at its defaults: bed friction the
  // soil's stop angle, the core at its repose angle, raining; and without
  // raining (the hydrostatic shallow layer).
  // And the flow the sessions run (terrain::session_flow_parameters:
  // owning its cells, the mean speed's lay-down, gathering steps).
  struct Variant {
    std::string name;
    GroundModel model;
    bool momentum, raining, sessions_flow = false;
  };
  // The fast flow at its defaults also at 2.5 cm (40 per radius): how far
  // the 10 and 5 cm figures are from the grid-converged model.
  auto cells_of = [&](const auto& v) {
    std::vector<double> out = cells;
    if (!ctx.quick && v.momentum && v.raining && !v.sessions_flow) out.push_back(0.025);
    return out;
  };
  const std::vector<Variant> variants =
      ctx.quick ? std::vector<Variant>{{"automaton", GroundModel::kAutomaton, false, false}}
                : std::vector<Variant>{{"automaton", GroundModel::kAutomaton, false, false},
                                       {"slippage", GroundModel::kSlippage, false, false},
                                       {"automaton + momentum", GroundModel::kAutomaton, true, true},
                                       {"the sessions' flow", GroundModel::kAutomaton, true, true, true},
                                       {"momentum, hydrostatic", GroundModel::kAutomaton, true, false}};

  Curve runout_dem{"DEM", {}}, height_dem{"DEM", {}};
  std::vector<Curve> runout_sk, height_sk, fronts;
  std::vector<Rung> rungs;
  std::string rows;
  for (const DemColumn& d : dem) {
    if (!standing_tube(d)) continue;
    runout_dem.points.emplace_back(d.released_aspect, d.runout), height_dem.points.emplace_back(d.released_aspect, d.height);
  }
  for (const DemColumn& d : dem)
    if (standing_tube(d) && d.aspect == 2.0) fronts.push_back({"DEM, tube a = 2", d.front});
  std::vector<std::string> cells_rows(dem.size());
  for (const Variant& v : variants) {
    for (double cell : cells_of(v)) {
      terrain::SoilFlowParameters soil = sand;
      soil.model = v.model;
      const std::string label = v.name + ", " + fmt("%g", cell * 100.0) + " cm";
      Curve runout_curve{label, {}}, height{label, {}};
      double worst = 0.0, wall = 0.0, simulated = 0.0;
      bool books = true;
      for (std::size_t k = 0; k < dem.size(); ++k) {
        const DemColumn& d = dem[k];
        CollapseCase c = dem_column_case(d, cell, v.momentum, v.raining);
        if (v.sessions_flow) c.momentum_params = terrain::session_flow_parameters(c.momentum_params);
        const CollapseRun run = terrain::run_column_collapse(c, soil);
        worst = std::max(worst, column_error(d, run));
        wall += run.wall_s, simulated += run.steps * c.step_dt_s;
        books = books && run.books_exact;
        if (standing_tube(d))
          runout_curve.points.emplace_back(d.released_aspect, run.runout_over_r0), height.points.emplace_back(d.released_aspect, run.final_height_over_r0);
        const auto front = scaled_front(run);
        if (standing_tube(d) && d.aspect == 2.0) {
          Curve f{label, {}};
          for (const auto& p : front)
            if (p.first <= 12.0) f.points.push_back(p);
          fronts.push_back(f);
        }
        cells_rows[k] += " | " + fmt("%.2f", compared_runout(d, run)) + " / " + fmt("%.2f", run.final_height_over_r0) + " / " +
                         fmt("%.1f", front_arrival(front, 0.9)) + " / " + fmt("%.2f", mass_gap(deposit_profile(run), d.deposit)) +
                         (run.at_rest ? "" : " (moving)");
      }
      runout_sk.push_back(runout_curve), height_sk.push_back(height);
      rungs.push_back({label, simulated > 0.0 ? wall / simulated : 0.0, worst,
                       std::string("books ") + (books ? "exact" : "NOT exact") + " over every run"});
    }
  }
  std::string header = "| column | DEM: run-out / height / t90 |";
  std::string rule = "|---|---|";
  for (const Variant& v : variants)
    for (double cell : cells_of(v)) {
      header += " " + v.name + ", " + fmt("%g", cell * 100.0) + " cm |";
      rule += "---|";
    }
  for (std::size_t k = 0; k < dem.size(); ++k)
    rows += "| " + column_name(dem[k]) + " | " + fmt("%.2f", compared_runout(dem[k])) + " / " + fmt("%.2f", dem[k].height) + " / " +
            fmt("%.1f", front_arrival(dem[k].front, 0.9)) + cells_rows[k] + " |\n";
  // The same grains in a tube twice as wide (25 grains per radius): the
  // model's dependence on r0 / d against the DEM's.
  std::string wide_rows;
  const std::vector<double> wide_cells = ctx.quick ? std::vector<double>{0.1} : std::vector<double>{0.1, 0.05, 0.025};
  for (const DemColumn& d : read_dem_columns(dem_dir, kWideTubeResults)) {
    wide_rows += "| " + column_name(d) + " | " + fmt("%.2f", d.runout) + " / " + fmt("%.2f", d.edge_runout) + " / " +
                 fmt("%.2f", d.height) + " / " + fmt("%.1f", front_arrival(d.front, 0.9));
    for (double cell : wide_cells) {
      const CollapseRun run = terrain::run_column_collapse(wide_tube_case(d, cell), sand);
      wide_rows += " | " + fmt("%.2f", run.runout_over_r0) + " / " + fmt("%.2f", run.edge_runout_over_r0) + " / " +
                   fmt("%.2f", run.final_height_over_r0) + " / " + fmt("%.1f", front_arrival(scaled_front(run), 0.9)) +
                   (run.at_rest ? "" : " (moving)");
    }
    wide_rows += " |\n";
  }
  std::string wide_header = "| column | DEM |", wide_rule = "|---|---|";
  for (double cell : wide_cells) wide_header += " automaton + momentum, " + fmt("%g", cell * 100.0) + " cm |", wide_rule += "---|";

  ReportSection s;
  std::vector<Curve> runout_curves{runout_dem}, height_curves{height_dem};
  runout_curves.insert(runout_curves.end(), runout_sk.begin(), runout_sk.end());
  height_curves.insert(height_curves.end(), height_sk.begin(), height_sk.end());
  const std::string runout_svg = ctx.svg_name("collapse_runout"), height_svg = ctx.svg_name("collapse_height"),
                    front_svg = ctx.svg_name("collapse_front"), error_svg = ctx.svg_name("collapse_error");
  s.svgs.emplace_back(runout_svg, svg_curves("Run-out against aspect ratio (tube)", "a = H0 / r0", "(r99 - r99 at release) / r0", runout_curves));
  s.svgs.emplace_back(height_svg, svg_curves("Final height against aspect ratio (tube)", "a = H0 / r0", "H / r0", height_curves));
  s.svgs.emplace_back(front_svg, svg_curves("The front against time, tube a = 2", "t / sqrt(H0 / g)", "(r99 - r99 at release) / r0", fronts));
  s.svgs.emplace_back(error_svg, svg_plot("Collapsing columns: worst error against the DEM", "worst relative error (run-out, height)", rungs));
  s.markdown =
      "## Collapsing columns against the DEM reference\n\n"
      "Granular columns released on a rough floor (dem/collapse, LIGGGHTS; scripts/dem_reference.sh, stages collapse "
      "and collapse_post): axisymmetric columns of radius r0 = 0.1 m and aspect ratio a = H0 / r0, and a column "
      "between the walls of a slot 0.08 m wide, in the calibrated DEM material. skidsim's column is the same in "
      "dimensionless form, scaled to r0 = 1 m in `dem_sand` (whose repose angle comes from the DEM's pile and its "
      "flowing friction from the DEM's inclined layer), "
      "so that 10 and 5 cm cells are 10 and 20 per radius; collapses of cohesionless grains depend on a, the "
      "material's friction and r0 / d (Lajeunesse et al. 2004, Lube et al. 2004, Warnett et al. 2014), so the grains "
      "are scaled with r0 too. Run-out: the advance of the "
      "distance within which 99 % of the mass lies, over r0; height: the column's at the axis (or the back wall) "
      "at rest, over r0; t90: when the front first reaches 90 % of its final advance, over sqrt(H0 / g). "
      "The automaton moves soil at most at its rolling-layer rate and stops it at the repose angle, so fast flows "
      "run out short and stand tall; the slippage model likewise. \"automaton + momentum\" is the fast-flow "
      "prototype (terrain/momentum_flow.h, docs/fast_flows.md): everything above the stable core (the highest "
      "surface no steeper than the repose angle, " + fmt("%.1f", sand.repose_angle_deg) + " deg) fails, falls "
      "freely and lands on a flowing layer without horizontal momentum (raining, Larrieu et al. 2006); the layer "
      "carries velocities on the cells' faces (Savage-Hutter, Coulomb friction on its bed at the soil's flowing "
      "friction, " + fmt("%.1f", sand.flowing_friction_deg()) + " deg, the mu_s of the mu(I) law, rising in "
      "layers a few grains thick as Pouliquen's law has it, read on the depth the layer moves in (its own over a bed "
      "that holds, with the bed over one that erodes), with the grains (and h_stop) scaled with r0; on the "
      "bare floor at the floor's, " + fmt("%.2f", dem.front().floor_friction_deg) + " deg; in the slot, also on its side walls at " +
      fmt("%.1f", dem.front().slot_wall_friction_deg) + " deg; all from the DEM's inclined layers, "
      "dem/calibration/chute.in) until friction stops it, eroding, down to the thick layer's flowing friction, what "
      "the avalanche laid down and the bed it found where that bed stands past its start angle (" +
      fmt("%.1f", sand.bed_start_angle_deg) + " deg, the DEM's erodible bed); it runs beside the automaton, which keeps the slow avalanches. \"the "
      "sessions' flow\" is that flow set up as the sessions run it: owning the cells it moves (the automaton off them) and "
      "laying a slowing layer's base down at the mean speed's rate, what it lays down then holding as the bed the event found "
      "(eroded only past its start angle), its thin fronts fed along their taper, gathering the world's steps while it is "
      "slow (docs/fast_flows.md, \"Which flow the sessions run\", \"The front's taper\", \"What a layer lays down\"). "
      "\"momentum, hydrostatic\" is the same "
      "without raining: the failed mass flows at once. The dropped column (a = 1 let go 4 r0 above the floor, as a "
      "bucket's load dumped from 2 m) falls as parcels (terrain/material_exchange.h) that land with their momentum "
      "and, with the fast flow, fall through the moving layer to the bed and press on the layer with their impact (as "
      "every landing does whose sheet would cross a cell before its friction stops it; all of this one's do), "
      "speeding it up to a stagnation flow's speed, at most the sheet speed " +
      fmt("%.2f", sand.impact_sheet_speed_ratio) + " of their free fall (a DEM granular jet's, dem/calibration/results/impact_summary.csv); "
      "its impact scatters single grains far out in the DEM, which no height field holds, so its run-out is the "
      "edge's (a quarter grain thick) rather than r99's. The fast flow runs at 2.5 cm too (40 cells per radius): "
      "how far the sessions' 10 and 5 cm cells are from the grid-converged model. Mass gap: where the deposit holds "
      "its mass against the DEM's, the largest difference, at any distance from the axis (the back wall), between the "
      "shares of the mass the two hold within it (Kolmogorov-Smirnov's distance; 0 where the mass lies alike, the "
      "DEM's scattered grains included). Each cell: run-out / height / t90 / mass gap.\n\n" +
      header + "\n" + rule + "\n" + rows + "\n"
      "The same grains in a tube twice as wide (r0 = 0.2 m, 25 grains per radius; dem/collapse/results_r0_0.2), the "
      "model's grains 0.04 r0. The DEM's r99 barely changes from 12.5 to 25 grains per radius; its edge (a quarter "
      "grain thick: 0.02 r0, then 0.01 r0) moves out to r99. Each cell: r99 / edge / height / t90.\n\n" +
      wide_header + "\n" + wide_rule + "\n" + wide_rows + "\n"
      "The same tubes in materials whose grains' rolling friction is 0.6 and 0.15 for the calibrated 0.3 "
      "(dem/collapse/results_mu_r0.6 and results_mu_r0.15, stage friction), each calibrated on the pile, the inclined "
      "layers and the erodible bed alone; the model takes each material's calibration and nothing from the tubes. "
      "Each cell: r99 / height over r0.\n\n" + friction_study_table(dem_dir, dem, sand, cells) + "\n"
      "A heap fed at a known rate (dem/calibration/fed_heap.in, stages fed_heap and fed_heap_post): grains rain at Q "
      "(bulk m^2/s per metre of width) onto the top of a quasi-two-dimensional heap 0.32 m long against a wall and "
      "run off its open edge; the slope (the least-squares line through the heap's height from 0.08 m off the wall to "
      "0.06 m short of the edge) from 6 to 20 s. The DEM's heap sheds its feed in surges (the 5th and 95th "
      "percentiles: about where they stop and where they start). skidsim's heap is the same scaled by " +
      fmt("%g", kFedHeapLambda) + " (experiments/fed_heap.h), its slope averaged over the same window, the automaton "
      "alone and with the fast flow, the feed landing with its fall. Each cell: the mean slope in degrees.\n\n" + fed_heap_table(dem_dir, sand, cells) + "\n"
      "The columns at the grain size of a laboratory or a session, against the published run-out law for "
      "axisymmetric collapses, (r_inf - r0) / r0 = 1.24 a below a = 1.7 and 1.6 a^0.5 above (Lube et al. 2004, on "
      "sand, salt, rice, couscous and sugar alike; independent of the DEM): tubes at r0 = 1 m with the soils' own "
      "grains (dem_sand's 8 mm: 125 per radius; the sessions' sands have no thin-layer law) and their bed's friction "
      "on the floor; dem_sand with the fast flow's defaults (the automaton sharing the flow's cells, as in the tables "
      "above) and the sessions' sands with the flow the sessions run (owning its cells, the mean speed's lay-down, "
      "gathering steps: docs/fast_flows.md, \"Which flow the sessions run\"; dry_sand, lete_sand: Coulomb at their stop angles, " +
      fmt("%.0f", soils.at("dry_sand").flow.flowing_friction_deg()) + " and " +
      fmt("%.0f", soils.at("lete_sand").flow.flowing_friction_deg()) + " deg, where dem_sand's flowing friction is " +
      fmt("%.1f", sand.flowing_friction_deg()) + " deg). Each cell: run-out (r99) / height over r0.\n\n" +
      published_laws_table(soils, cells) + "\n" + table(rungs, "worst relative error (run-out, height)", kCostPerSimulatedSecond, "model, cells") +
      "\n![" + runout_svg + "](" + runout_svg + ") ![" + height_svg + "](" + height_svg + ")\n\n![" + front_svg + "](" +
      front_svg + ") ![" + error_svg + "](" + error_svg + ")\n";
  return s;
}

}  // namespace skidsim::report::perf
