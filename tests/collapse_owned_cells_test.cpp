// The fast flow owning its cells (MomentumFlowParameters::owns_cells: the
// automaton off the flowing layer's cells, the layer laying its base down as
// it slows), a study beside the shipped model, against the same independent
// references: the published run-out law with the sessions' sands, the DEM's
// calibrated tubes at 12.5 and 25 grains per radius, its dropped column and
// slot, and the friction study's three materials. docs/fast_flows.md, "A
// flow that owns its cells" and "A layer coming to rest".
//
// Two depositions (MomentumFlowParameters::Deposition). The mean speed's
// rule (kMeanSpeed), the first written, comes within a fifth of the
// collapses' run-outs (held below as it was measured), but lays a slowing layer down at twice
// the rate of the interface's and stops a layer's mass in half the DEM's
// travel (dem_stopping_reference_test.cpp): its agreement rests on that
// factor making up for a friction that does not rise with speed as the
// DEM's layers' does. The interface's (kInterface, the default), which the
// DEM's stopping layers follow, runs the collapses long with the stop
// friction alone (longer than the mean speed's rule: held with the
// sessions' sands, which give no grain size, hence no rise); with the
// friction's rise with the inertial number (rate_friction, fitted on the
// inclined layers, within 10 % of the stopping layers' friction) it meets
// the tubes' run-outs at 25 grains per radius and comes within a fifth at
// 12.5, its heights within a fifth (a = 4 lowest), but not yet the other
// materials ("The friction at speed").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "experiments/column_collapse.h"
#include "io/soil_table.h"
#include "report/dem_columns.h"
#include "report/perf_report_parts.h"

namespace skidsim::report::perf {
namespace {

using Deposition = terrain::MomentumFlowParameters::Deposition;

terrain::CollapseRun run_owned(terrain::CollapseCase c, const terrain::SoilFlowParameters& soil,
                               Deposition deposition = Deposition::kMeanSpeed) {
  c.momentum_params.owns_cells = true;
  c.momentum_params.deposition = deposition;
  return terrain::run_column_collapse(c, soil);
}

// The interface's deposition with the friction's rise (the DEM's materials),
// read on the flowing layer: under the interface the laid-down grains are at
// rest, and a layer on a bed at rest rubs at its own thickness's friction
// (the DEM's erodible bed; docs/fast_flows.md, "The friction at speed").
terrain::CollapseRun run_owned_rising(terrain::CollapseCase c, const terrain::SoilFlowParameters& soil) {
  c.momentum_params.rate_friction = true;
  c.momentum_params.layer_depth = terrain::MomentumFlowParameters::LayerDepth::kFlowing;
  return run_owned(c, soil, Deposition::kInterface);
}

// The sessions' sands, 15-44 % short of the published law with the shipped
// model (collapse_published_laws_test.cpp), come within 11 % at 10 and 5 cm
// with the flow the sessions run (terrain::session_flow_parameters: owning
// its cells, the mean speed's lay-down, its fronts fed along their taper,
// gathering steps; dry_sand -3 to +6 %, lete_sand -11 to -2 %). Gathering
// steps moves no run-out by more than 0.7 % and no height by more than
// 1.7 % (held at 3 %).
TEST(FlowOwningItsCells, TheSessionsSandsMeetThePublishedLaw) {
  const auto table = io::load_soil_table(io::default_soil_table_path());
  for (const char* name : {"dry_sand", "lete_sand"}) {
    for (double cell : {0.1, 0.05}) {
      for (double a : {0.5, 1.0, 2.0, 4.0}) {
        terrain::CollapseCase c = terrain::laboratory_column_case(a, cell);
        c.momentum_params = terrain::session_flow_parameters();
        const terrain::CollapseRun run = terrain::run_column_collapse(c, table.at(name).flow);
        c.momentum_params.gather_steps = false;
        const terrain::CollapseRun every_step = terrain::run_column_collapse(c, table.at(name).flow);
        const terrain::CollapseRun interface = run_owned(c, table.at(name).flow, Deposition::kInterface);
        const double law = terrain::published_runout_over_r0(a), error = run.runout_over_r0 / law - 1.0;
        std::printf("[ measured ] the sessions' flow, %s, a = %g at %g m: run-out %.2f r0 (published law %.2f, %+.1f %%; "
                    "a sub-step every step %.3f, gathering %.3f; the interface's %.2f, %+.1f %%), height %.3f r0 (a sub-step every "
                    "step %.3f; the interface's %.2f)\n",
                    name, a, cell, run.runout_over_r0, law, 100.0 * error, every_step.runout_over_r0, run.runout_over_r0,
                    interface.runout_over_r0, 100.0 * (interface.runout_over_r0 / law - 1.0), run.final_height_over_r0,
                    every_step.final_height_over_r0, interface.final_height_over_r0);
        const std::string where = std::string(name) + ", a = " + std::to_string(a) + ", " + std::to_string(cell) + " m";
        EXPECT_TRUE(run.books_exact && run.flow_at_rest) << where;
        EXPECT_TRUE(interface.books_exact && interface.flow_at_rest) << where;
        EXPECT_LT(std::abs(error), 0.15) << where;
        EXPECT_NEAR(run.runout_over_r0, every_step.runout_over_r0, 0.03 * every_step.runout_over_r0) << where;
        EXPECT_NEAR(run.final_height_over_r0, every_step.final_height_over_r0, 0.03 * every_step.final_height_over_r0) << where;
        EXPECT_GT(interface.runout_over_r0, run.runout_over_r0) << where;
      }
    }
  }
}

// dem_sand against its DEM's standing tubes (a = 0.5 to 4 at 12.5 grains per
// radius, 0.5 to 2 at 25), each collapsed as it was released. The mean
// speed's rule: r99 -5 to -20 % at 12.5 grains per radius and -9 to +7 %
// at 25, at 10 and 5 cm (the shipped model: 19-34 % short; held at 22 %);
// heights +2 to -19 % (held at 20 %). The interface with the friction's
// rise: r99 -7 to -19 % at 12.5 grains per radius (held at 20 %), -1 to
// +6 % at 25 (held at 10 %); heights +5 to -18 %, a = 4 and the wide a = 2
// lowest (held at 20 %).
TEST(FlowOwningItsCells, TheCalibratedTubesAgainstTheDem) {
  const terrain::SoilFlowParameters sand = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  for (const char* folder : {"results", kWideTubeResults}) {
    for (const DemColumn& d : read_dem_columns(repository_dem_dir(), folder)) {
      if (!standing_tube(d)) continue;
      for (double cell : {0.1, 0.05}) {
        const terrain::CollapseCase c = dem_column_case(d, cell, true, true);
        const terrain::CollapseRun run = run_owned(c, sand), shipped = terrain::run_column_collapse(c, sand);
        const terrain::CollapseRun interface = run_owned_rising(c, sand);
        std::printf("[ measured ] owning its cells, %s, %.1f grains per radius, a = %g at %g r0: r99 %.2f (DEM %.2f, %+.1f %%; shipped %.2f; "
                    "the interface's with the rise %.2f, %+.1f %%), edge %.2f (DEM %.2f; shipped %.2f), height %.2f (DEM %.2f, %+.1f %%; "
                    "shipped %.2f; the interface's with the rise %.2f, %+.1f %%)\n",
                    folder, 1.0 / d.grain_diameter_over_r0, d.aspect, cell, run.runout_over_r0, d.runout, 100.0 * (run.runout_over_r0 / d.runout - 1.0),
                    shipped.runout_over_r0, interface.runout_over_r0, 100.0 * (interface.runout_over_r0 / d.runout - 1.0),
                    run.edge_runout_over_r0, d.edge_runout, shipped.edge_runout_over_r0,
                    run.final_height_over_r0, d.height, 100.0 * (run.final_height_over_r0 / d.height - 1.0),
                    shipped.final_height_over_r0, interface.final_height_over_r0,
                    100.0 * (interface.final_height_over_r0 / d.height - 1.0));
        const std::string where = std::string(folder) + ", " + column_name(d) + ", " + std::to_string(cell);
        EXPECT_TRUE(run.books_exact && run.flow_at_rest) << where;
        EXPECT_TRUE(interface.books_exact && interface.flow_at_rest) << where;
        EXPECT_LT(std::abs(run.runout_over_r0 / d.runout - 1.0), 0.22) << where;
        EXPECT_LT(std::abs(run.final_height_over_r0 / d.height - 1.0), 0.20) << where;
        const bool coarse = d.grain_diameter_over_r0 > 0.06;  // 12.5 grains per radius
        EXPECT_LT(std::abs(interface.runout_over_r0 / d.runout - 1.0), coarse ? 0.20 : 0.10) << where;
        EXPECT_LT(std::abs(interface.final_height_over_r0 / d.height - 1.0), 0.20) << where;
      }
    }
  }
}

// The flow the sessions run (terrain::session_flow_parameters: owning its
// cells, the mean speed's lay-down, its fronts fed along their taper, what
// it lays down holding as bed, gathering steps) against every DEM column,
// each collapsed as released, at the sessions' 10 and 5 cm cells
// (docs/fast_flows.md, "The front's taper" and "What a layer lays down").
// Measured at 12.5 grains per radius: r99 -7.5 to +7.2 % on the tubes and
// the slot, -4.8 / -10.7 % on the dropped column's edge (held at 15 %);
// heights -12.9 to +1.9 % (held at 15 %); t90 -15.8 to -4.4 % at a >= 1
// and on the slot (held at 20 %). a = 0.5's t90 is -21.1 %: that column
// stands six grains tall, and the DEM's own t90 comes 11 % sooner with
// twice the grains per radius, against which the model's is -8.7 % (held
// at 25 % here, 20 % there). r99 at 10 and 5 cm within 0.04 r0 of each
// other (held at 0.06 r0: the rule does not depend on the cell size, where
// the next cell's feed left 5 cm 0.05-0.15 r0 short of 10 cm); the dropped
// column's edge, read in whole cells, 1.60 / 1.50 r0 (held within a 10 cm
// and a 5 cm cell, 0.15 r0). At 25 grains per radius r99 +0.7 to +9.7 %, heights +0.1
// to -15.1 %, t90 -10.7 to -5.4 % (held at 12, 16 and 20 %).
TEST(FlowOwningItsCells, TheSessionsFlowAgainstEveryDemColumnAtTwoCellSizes) {
  const terrain::SoilFlowParameters sand = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  for (const char* folder : {"results", kWideTubeResults}) {
    const bool wide = std::string(folder) == kWideTubeResults;
    for (const DemColumn& d : read_dem_columns(repository_dem_dir(), folder)) {
      double r99_at[2] = {0.0, 0.0};
      for (int k = 0; k < 2; ++k) {
        const double cell = k == 0 ? 0.1 : 0.05;
        terrain::CollapseCase c = dem_column_case(d, cell, true, true);
        c.momentum_params = terrain::session_flow_parameters(c.momentum_params);
        const terrain::CollapseRun run = terrain::run_column_collapse(c, sand);
        // A dropped column's impact scatters grains far out one by one, which
        // no height field holds: its edge (DemColumn).
        const bool dropped = d.drop_over_r0 > 0.0;
        const double runout = dropped ? run.edge_runout_over_r0 / d.edge_runout - 1.0 : run.runout_over_r0 / d.runout - 1.0;
        const double height = run.final_height_over_r0 / d.height - 1.0;
        const double t90 = front_arrival(scaled_front(run), 0.9) / front_arrival(d.front, 0.9) - 1.0;
        r99_at[k] = dropped ? run.edge_runout_over_r0 : run.runout_over_r0;
        const std::string where = std::string(folder) + ", " + column_name(d) + ", " + std::to_string(cell) + " m";
        std::printf("[ measured ] the sessions' flow, %s: %s %+.1f %%, height %+.1f %%, t90 %+.1f %%, mass gap %.3f, edge %.2f (DEM %.2f)\n",
                    where.c_str(), dropped ? "edge" : "r99", 100.0 * runout, 100.0 * height, 100.0 * t90,
                    mass_gap(deposit_profile(run), d.deposit), run.edge_runout_over_r0, d.edge_runout);
        EXPECT_TRUE(run.books_exact && run.flow_at_rest) << where;
        EXPECT_LT(std::abs(runout), wide ? 0.12 : 0.15) << where;
        if (dropped) continue;  // its middle: ADroppedColumnSpreadsWithItsImpactAsTheDemsDoes
        EXPECT_LT(std::abs(height), wide ? 0.16 : 0.15) << where;
        EXPECT_LT(std::abs(t90), wide || d.aspect >= 1.0 ? 0.20 : 0.25) << where;
      }
      // The dropped column's edge is read in whole cells, each reading good
      // to its own cell: within a 10 cm and a 5 cm cell of each other (0.15 r0).
      const bool dropped = d.drop_over_r0 > 0.0;
      EXPECT_NEAR(r99_at[1], r99_at[0], dropped ? 0.15 : 0.06) << folder << ", " << column_name(d) << ": 5 against 10 cm";
    }
  }
}

// What a slowing layer lays down holds as bed (laid_down_holds, on in the
// sessions' flow) only on a soil with a bed start angle: on dem_sand a = 4's
// middle stands taller with it (0.834 r0 for 0.814 at 10 cm: the next layer
// no longer carries off what came to rest on it, as the DEM's grains at
// rest stay at rest), and on the sessions' sands, which have none, the
// deposit, its run-out, edge and height and the steps it took are the same
// to the last bit (docs/fast_flows.md, "What a layer lays down").
TEST(FlowOwningItsCells, WhatALayerLaysDownHoldsOnlyOnASoilWithABedStartAngle) {
  const auto table = io::load_soil_table(io::default_soil_table_path());
  bool found_a4 = false;
  for (const DemColumn& d : read_dem_columns(repository_dem_dir())) {
    if (!standing_tube(d) || d.aspect != 4.0) continue;
    found_a4 = true;
    terrain::CollapseCase c = dem_column_case(d, 0.1, true, true);
    c.momentum_params = terrain::session_flow_parameters(c.momentum_params);
    const terrain::CollapseRun holds = terrain::run_column_collapse(c, table.at("dem_sand").flow);
    c.momentum_params.laid_down_holds = false;
    const terrain::CollapseRun erodes = terrain::run_column_collapse(c, table.at("dem_sand").flow);
    std::printf("[ measured ] dem_sand, a = 4 at 0.1 m: height %.3f r0 with what it lays down holding, %.3f without (DEM %.2f)\n",
                holds.final_height_over_r0, erodes.final_height_over_r0, d.height);
    EXPECT_TRUE(holds.books_exact && erodes.books_exact);
    EXPECT_GT(holds.final_height_over_r0, erodes.final_height_over_r0 + 0.01);
  }
  EXPECT_TRUE(found_a4) << "the DEM's tube a = 4 (dem/collapse/results)";
  for (const char* name : {"dry_sand", "lete_sand"}) {
    terrain::CollapseCase c = terrain::laboratory_column_case(2.0, 0.1);
    c.momentum_params = terrain::session_flow_parameters();
    const terrain::CollapseRun holds = terrain::run_column_collapse(c, table.at(name).flow);
    c.momentum_params.laid_down_holds = false;
    const terrain::CollapseRun erodes = terrain::run_column_collapse(c, table.at(name).flow);
    EXPECT_GT(holds.runout_over_r0, 1.0) << name;
    EXPECT_EQ(holds.deposit_volume_m3, erodes.deposit_volume_m3) << name;
    EXPECT_EQ(holds.runout_over_r0, erodes.runout_over_r0) << name;
    EXPECT_EQ(holds.edge_runout_over_r0, erodes.edge_runout_over_r0) << name;
    EXPECT_EQ(holds.final_height_over_r0, erodes.final_height_over_r0) << name;
    EXPECT_EQ(holds.steps, erodes.steps) << name;
  }
}

// The landing and the channel, each collapsed as released: with the mean
// speed's rule the dropped column stops short (edge 1.40 / 1.35 r0 for the
// DEM's 1.68, the shipped model's 2.00 / 1.65) and the slot's r99 comes
// within 8 % (-6 / -8 %); the interface with the rise spreads the dropped
// column to +7 / +4 % on the edge and runs the slot +8 / +6 % on r99 (10 /
// 5 cm; the shipped model's -19 / -18 %), its height -11 / -10 %. Held
// here: exact books and rest.
TEST(FlowOwningItsCells, TheDroppedColumnAndTheSlotKeepExactBooks) {
  const terrain::SoilFlowParameters sand = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  for (const DemColumn& d : read_dem_columns(repository_dem_dir())) {
    if (standing_tube(d)) continue;
    for (double cell : {0.1, 0.05}) {
      const terrain::CollapseCase c = dem_column_case(d, cell, true, true);
      const terrain::CollapseRun run = run_owned(c, sand), shipped = terrain::run_column_collapse(c, sand);
      const terrain::CollapseRun interface = run_owned_rising(c, sand);
      std::printf("[ measured ] owning its cells, %s at %g r0: r99 %.2f (DEM %.2f; shipped %.2f; the interface's with the rise %.2f), edge %.2f "
                  "(DEM %.2f; shipped %.2f; the interface's with the rise %.2f), height %.2f (DEM %.2f; shipped %.2f; the interface's with the rise %.2f)\n",
                  column_name(d).c_str(), cell, run.runout_over_r0, d.runout, shipped.runout_over_r0, interface.runout_over_r0,
                  run.edge_runout_over_r0, d.edge_runout, shipped.edge_runout_over_r0, interface.edge_runout_over_r0,
                  run.final_height_over_r0, d.height, shipped.final_height_over_r0, interface.final_height_over_r0);
      EXPECT_TRUE(run.books_exact && run.flow_at_rest) << column_name(d) << ", " << cell;
      EXPECT_TRUE(interface.books_exact && interface.flow_at_rest) << column_name(d) << ", " << cell;
    }
  }
}

// The friction study's materials: the owning flow's run-outs stand in the
// DEM's order (the smoother longer, the rougher shorter) but apart
// faintly: r99 +10 % and -4 % at a = 1 where the DEM's moves +65 and
// -26 % (the interface with the rise, each material's own: +10 % and
// -3 %). Its deposition keeps the same share of a slowing layer's
// thickness on every material, where the DEM's profiles
// (profile_summary.csv) show the smoother grains' base sliding (28-46 % of
// the top's speed behind the front) and the rougher's at rest (3-6 %).
TEST(FlowOwningItsCells, FollowsTheMaterialTheDemsWayButFaintly) {
  const terrain::SoilFlowParameters sand = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  // Smoother, calibrated, rougher: each material's soil and DEM columns, read once.
  const char* folders[3] = {kFrictionStudy[1].results, "results", kFrictionStudy[0].results};
  std::vector<terrain::SoilFlowParameters> soils;
  std::vector<std::vector<DemColumn>> columns;
  for (const char* folder : folders) {
    soils.push_back(calibrated_flow(columns_material(repository_dem_dir(), folder), sand));
    columns.push_back(read_dem_columns(repository_dem_dir(), folder));
  }
  soils[1] = sand;  // dem_sand's own table (its calibration's: dem_friction_study_test)
  for (double cell : {0.1, 0.05}) {
    for (double a : {0.5, 1.0, 2.0}) {
      double r99[2][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};  // the mean speed's rule, the interface's with the rise
      for (int m = 0; m < 3; ++m)
        for (const DemColumn& d : columns[m])
          if (standing_tube(d) && d.aspect == a) {
            for (int k = 0; k < 2; ++k) {
              const terrain::CollapseCase c = dem_column_case(d, cell, true, true);
              const terrain::CollapseRun run = k == 0 ? run_owned(c, soils[m]) : run_owned_rising(c, soils[m]);
              EXPECT_TRUE(run.books_exact && run.flow_at_rest) << folders[m] << ", a = " << a;
              r99[k][m] = run.runout_over_r0;
            }
            std::printf("[ measured ] owning its cells, %s, a = %g at %g r0: r99 %.2f, the interface's with the rise %.2f (DEM %.2f)\n",
                        folders[m], a, cell, r99[0][m], r99[1][m], d.runout);
          }
      for (int k = 0; k < 2; ++k) {
        ASSERT_GT(r99[k][1], 0.0);
        EXPECT_GT(r99[k][0], r99[k][1]) << "a = " << a << ", " << cell << ", deposition " << k;
        EXPECT_GT(r99[k][1], r99[k][2]) << "a = " << a << ", " << cell << ", deposition " << k;
      }
    }
  }
}

}  // namespace
}  // namespace skidsim::report::perf
