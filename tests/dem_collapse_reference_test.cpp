// skidsim's collapsing columns against the stored LIGGGHTS columns
// (dem/collapse/results; scripts/dem_reference.sh): the fast flow
// (terrain/momentum_flow.h) in dem_sand, whose repose angle comes from the
// DEM's pile and whose flowing friction, like the deck's floor and slot
// walls, from the DEM's inclined layers (dem/calibration/chute.in), never
// from these runs, at the sessions' 10 and 5 cm cells (10 and 20 per
// radius), in run-out and final height over r0 and the front's arrival over
// sqrt(H0 / g) (report/dem_columns.h).
//
// The grains' size scales with r0 too (0.08 r0; 0.04 r0 in the tube twice
// as wide): a thin layer's friction depends on its thickness in grains
// (Pouliquen 1999), as the chute measured;
// the thickness it reads is the depth the layer moves in: its own on a bed
// at rest below its start angle, as the DEM's erodible bed shows
// (DemErodibleBed, last), with the bed under it where that bed erodes (what
// the collapse laid down, a bed past its start angle).
//
// Each DEM column is collapsed as it was released (its released aspect
// ratio, dem/tools/collapse.py): the deck once left its tall columns short
// of H0 (docs/fast_flows.md, "The columns as released").
//
// The bounds hold what is reached against the columns as released
// (docs/fast_flows.md): the tubes' deposits round, their edges within 17 %
// and half a cell (-16 % at most, a = 2 at 5 cm; the edge is measured in
// whole cells), their r99 run-outs 19-34 % short (the DEM's deposit thins
// out in a toe the grid's thin layers do not hold), their heights within
// 15 % (+14 % at most, a = 4 at 5 cm: the tall columns stand tall), the
// slot's r99 18-19 % short (tested at 22 %) and its height within 10 %, the
// front's arrival within 20 % where the column falls; every deposit's mass
// where the DEM's lies within 0.13 of its share at every distance from the
// axis (mass_gap: 0.03-0.07); the landings: the dropped column's edge
// within 25 % and its height within 50 %, the granular jet's edge and
// centre within 30 %, a bucket's load dumped on the sessions' sands within
// 15 % of the DEM's edge. The aim of 15 % is reached on the tubes'
// heights and on the sands' dump's edge; not on the tubes' and the slot's
// r99 (nor the slot's edge, 29-32 % short, untested), the jet's edge, the
// dropped column's edge at 10 cm (+19 %) or the landings' heights (the owning flow, a study,
// comes closer on run-out: collapse_owned_cells_test.cpp). A change that
// loses ground fails; tighten them as the model improves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "common/physical_constants.h"
#include "io/soil_table.h"
#include "report/dem_columns.h"
#include "report/perf_report_parts.h"
#include "terrain/granular_grid.h"
#include "terrain/momentum_flow.h"

namespace skidsim::report::perf {
namespace {

namespace fs = std::filesystem;

struct Reference {
  std::vector<DemColumn> dem, wide;  // the tubes of r0 = 0.1 m and the slot; the tubes twice as wide
  io::SoilRecord sand;
};

const Reference& reference() {
  static const Reference s{read_dem_columns(repository_dem_dir()), read_dem_columns(repository_dem_dir(), kWideTubeResults),
                           io::load_soil_table(io::default_soil_table_path()).at("dem_sand")};
  return s;
}

// The mass gap on deposits whose shares are known: a disc's mass all in
// its first bin against a ring's all in the next, and a deposit against
// itself; the DEM's deposits each hold their whole mass.
TEST(DemCollapse, TheMassGapIsKolmogorovSmirnovsDistance) {
  const MassProfile inner{{1.0, 2.0}, {1.0, 0.0}}, outer{{1.0, 2.0}, {0.0, 1.0}};
  EXPECT_DOUBLE_EQ(mass_within(inner, 0.5), 0.5);  // linear within a bin
  EXPECT_DOUBLE_EQ(mass_within(outer, 1.5), 0.5);
  double at = 0.0;
  EXPECT_DOUBLE_EQ(mass_gap(inner, outer, &at), 1.0);
  EXPECT_DOUBLE_EQ(at, 1.0);
  EXPECT_DOUBLE_EQ(mass_gap(inner, inner), 0.0);
  const MassProfile half{{1.0, 2.0}, {0.5, 0.5}};
  EXPECT_DOUBLE_EQ(mass_gap(inner, half), 0.5);
  // Bins that do not line up (the grid's against the DEM's): the largest gap
  // on the finer profile's edge at 0.5, where it holds 0.4 and the coarse
  // one (a quarter per half bin) 0.25.
  const MassProfile fine{{0.5, 1.0, 1.5, 2.0}, {0.4, 0.1, 0.25, 0.25}}, coarse{{1.0, 2.0}, {0.5, 0.5}};
  EXPECT_DOUBLE_EQ(mass_gap(fine, coarse, &at), 0.15);
  EXPECT_DOUBLE_EQ(at, 0.5);
  EXPECT_DOUBLE_EQ(mass_gap(coarse, fine, &at), 0.15);
  EXPECT_DOUBLE_EQ(at, 0.5);
  for (const DemColumn& d : reference().dem) {
    EXPECT_NEAR(mass_within(d.deposit, 1e9), 1.0, 1e-12) << column_name(d);
    EXPECT_DOUBLE_EQ(mass_within(d.deposit, 0.0), 0.0) << column_name(d);
  }
}

// The DEM reference's columns and calibration copied to a scratch folder
// `name`, for a test to spoil.
fs::path copied_reference(const char* name) {
  const fs::path dem = repository_dem_dir();
  const fs::path copy = fs::temp_directory_path() / name;
  fs::remove_all(copy);
  fs::create_directories(copy / "collapse");
  fs::create_directories(copy / "calibration");
  fs::copy(dem / "collapse/results", copy / "collapse/results");
  fs::copy_file(dem / "calibration/material.csv", copy / "calibration/material.csv");
  return copy;
}

// Reading the reference in `dem` fails with a message holding `naming`.
void expect_refused(const fs::path& dem, const std::string& naming, const char* read_what) {
  try {
    read_dem_columns(dem);
    ADD_FAILURE() << "read " << read_what;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(naming), std::string::npos) << e.what();
  }
}

// A DEM reference without a column's deposit, or with one whose bins do
// not start at the axis, is refused, naming the file (and the row).
TEST(DemCollapse, AMissingDepositIsNamed) {
  const fs::path copy = copied_reference("skidsim_dem_columns_missing_deposit");
  fs::remove(copy / "collapse/results/deposit_tube_a2.csv");
  expect_refused(copy, "deposit_tube_a2.csv", "a reference without deposit_tube_a2.csv");
  std::ofstream(copy / "collapse/results/deposit_tube_a2.csv") << "r_m,thickness_m,top_m\n0.004,0.1,0.1\n0.012,0.1,0.1\n0.030,0.1,0.1\n";
  expect_refused(copy, "deposit_tube_a2.csv: row 4: r_m 0.03", "a deposit whose third bin is out of place");
  fs::remove_all(copy);
}

// A column without a released aspect ratio (a summary from before
// collapse.py wrote one, or a row that lost it) is refused, naming the file
// and the row: the model would collapse a column of no height.
TEST(DemCollapse, AColumnWithoutItsReleasedAspectIsNamed) {
  const fs::path copy = copied_reference("skidsim_dem_columns_released_aspect");
  const fs::path summary = copy / "collapse/results/summary.csv";
  // The summary's fields, row by row.
  std::vector<std::vector<std::string>> rows;
  {
    std::ifstream in(summary);
    for (std::string line; std::getline(in, line);) {
      rows.emplace_back();
      std::istringstream fields(line);
      for (std::string field; std::getline(fields, field, ',');) rows.back().push_back(field);
    }
  }
  ASSERT_GE(rows.size(), 3u);
  // The second column's released_aspect set to 0.
  const auto column = std::find(rows[0].begin(), rows[0].end(), "released_aspect") - rows[0].begin();
  ASSERT_LT(column, static_cast<std::ptrdiff_t>(rows[0].size()));
  rows[2][column] = "0";
  {
    std::ofstream out(summary);
    for (const auto& row : rows) {
      for (std::size_t k = 0; k < row.size(); ++k) out << (k ? "," : "") << row[k];
      out << "\n";
    }
  }
  expect_refused(copy, "summary.csv: row 3: released_aspect 0 is not > 0", "a column released at a = 0");
  fs::remove_all(copy);
}

TEST(DemCollapse, RunOutHeightAndFrontAgainstTheDemAtTwoCellSizes) {
  const Reference& s = reference();
  ASSERT_EQ(s.dem.size(), 6u);
  for (double cell : {0.1, 0.05}) {
    for (const DemColumn& d : s.dem) {
      if (d.drop_over_r0 > 0.0) continue;  // DroppedColumn
      const terrain::CollapseRun run =
          terrain::run_column_collapse(dem_column_case(d, cell, true, true), s.sand.flow);
      const std::string name = column_name(d) + ", " + std::to_string(cell) + " m";
      EXPECT_TRUE(run.books_exact) << name;
      // The flow stops (the automaton beside it may trickle a few quanta a
      // step on the deposit's steepest cells for longer).
      EXPECT_TRUE(run.flow_at_rest) << name;
      const double runout = run.runout_over_r0 / d.runout - 1.0, height = run.final_height_over_r0 / d.height - 1.0;
      const double t90 = front_arrival(scaled_front(run), 0.9), t90_dem = front_arrival(d.front, 0.9);
      std::printf("[ measured ] %s: run-out %.3f (DEM %.3f, %+.1f %%), height %.3f (DEM %.3f, %+.1f %%), edge %.2f (DEM %.2f), "
                  "t90 %.2f (DEM %.2f)\n",
                  name.c_str(), run.runout_over_r0, d.runout, 100.0 * runout, run.final_height_over_r0, d.height,
                  100.0 * height, run.edge_runout_over_r0, d.edge_runout, t90, t90_dem);
      if (d.slot) {
        EXPECT_LT(std::abs(runout), 0.22) << name << ": run-out " << run.runout_over_r0 << " against " << d.runout;
        EXPECT_LT(std::abs(height), 0.10) << name << ": height " << run.final_height_over_r0 << " against " << d.height;
      } else {
        // The edge (a quarter grain thick) within 17 % and half a cell (it
        // is measured in whole cells: a = 0.5's 0.4 r0 one cell short at
        // 5 cm, exact at 10 cm); r99 also counts the DEM's toe beyond it,
        // under 0.02 r0 thick and as long in r0 at twice the grains per
        // radius, which the grid's thin layers, stopping, do not hold.
        const double edge_error = std::abs(run.edge_runout_over_r0 - d.edge_runout);
        // Round, as the DEM's: the edge along the grid's diagonals as far as
        // along its axes within a cell and a tenth.
        const double axes = run.final_state.edge_along_axes_m, diagonals = run.final_state.edge_along_diagonals_m;
        std::printf("[ measured ] %s: edge along the axes %.2f r0, along the diagonals %.2f r0\n", name.c_str(),
                    axes / run.c.r0_m, diagonals / run.c.r0_m);
        EXPECT_NEAR(diagonals, axes, 0.1 * axes + cell) << name;
        EXPECT_LE(edge_error, 0.17 * d.edge_runout + 0.5 * cell / run.c.r0_m)
            << name << ": edge " << run.edge_runout_over_r0 << " against " << d.edge_runout;
        EXPECT_LT(std::abs(runout), 0.35) << name << ": run-out " << run.runout_over_r0 << " against " << d.runout;
        EXPECT_LT(std::abs(height), 0.15) << name << ": height " << run.final_height_over_r0 << " against " << d.height;
      }
      // Where the deposit holds its mass (r99 and the edge are two points of
      // it): at every distance from the axis (the wall) the share of the mass
      // within it is the DEM's within 0.13, the DEM's toe included (a = 4
      // the worst, 0.07 near 2.1 r0).
      double at = 0.0;
      const double gap = mass_gap(deposit_profile(run), d.deposit, &at);
      std::printf("[ measured ] %s: mass gap %.3f (at %.2f r0)\n", name.c_str(), gap, at);
      EXPECT_LE(gap, 0.13) << name << ": at " << at << " r0";
      // The front's arrival at 90 % of its advance, within 20 % where the
      // column falls (a >= 1); the low column's edge wedge slides out
      // sooner than the DEM's.
      if (d.aspect >= 1.0) {
        EXPECT_NEAR(t90 / t90_dem, 1.0, 0.2) << name << ": t90 " << t90 << " against " << t90_dem;
      }
    }
  }
}

// The same grains in a tube twice as wide (r0 = 0.2 m, 25 grains per radius:
// kWideTubeResults), the model's grains scaled with r0 as the DEM's are
// (0.04 r0), at the sessions' 10 and 5 cm cells. From 12.5 to 25 grains per
// radius the DEM's r99 and height hardly move (r99 0.50 to 0.52, 1.17 to
// 1.20 and 2.26 to 2.24 r0 at a = 0.5, 1 and 2) while its edge, where the
// deposit is a quarter grain thick, moves out to it (0.40 to 0.52, 0.96 to
// 1.16, 1.84 to 2.20): the deposit's sparse toe scales with r0, not with
// the grain (docs/fast_flows.md, "Twice the grains per radius"). The
// model's r99 grows with the grains per radius where the DEM's does not
// (its thin-layer law's decay length, A d, halves with d), yet stays short:
// -24 / -19 / -14 % at 10 cm, -28 / -24 / -16 % at 5 cm (a = 0.5 / 1 / 2;
// tested at 30 % and, a >= 1, 25 %); its edges within 14 % and its heights
// within 6 %; its fronts at a >= 1 late (t90 +7 to +13 %; tested at 25 %),
// at a = 0.5 early (-19 / -12 %).
TEST(DemCollapse, AtTwiceTheGrainsPerRadiusAgainstTheWiderDemTube) {
  const std::vector<DemColumn>& wide = reference().wide;
  ASSERT_EQ(wide.size(), 3u);
  for (double cell : {0.1, 0.05}) {
    for (const DemColumn& d : wide) {
      ASSERT_NEAR(d.grain_diameter_over_r0, 0.04, 1e-12);
      const terrain::CollapseRun run = terrain::run_column_collapse(wide_tube_case(d, cell), reference().sand.flow);
      const std::string name = column_name(d) + ", 25 grains per radius, " + std::to_string(cell) + " m";
      const double runout = run.runout_over_r0 / d.runout - 1.0, edge = run.edge_runout_over_r0 / d.edge_runout - 1.0;
      const double height = run.final_height_over_r0 / d.height - 1.0;
      const double t90 = front_arrival(scaled_front(run), 0.9), t90_dem = front_arrival(d.front, 0.9);
      const double gap = mass_gap(deposit_profile(run), d.deposit);
      std::printf("[ measured ] %s: r99 %.3f (DEM %.3f, %+.1f %%), edge %.2f (DEM %.2f, %+.1f %%), height %.3f (DEM %.3f, "
                  "%+.1f %%), t90 %.2f (DEM %.2f), mass gap %.3f\n",
                  name.c_str(), run.runout_over_r0, d.runout, 100.0 * runout, run.edge_runout_over_r0, d.edge_runout, 100.0 * edge,
                  run.final_height_over_r0, d.height, 100.0 * height, t90, t90_dem, gap);
      EXPECT_TRUE(run.books_exact) << name;
      EXPECT_TRUE(run.flow_at_rest) << name;
      EXPECT_LT(std::abs(edge), 0.15) << name;
      EXPECT_LT(std::abs(height), 0.15) << name;
      EXPECT_LE(gap, 0.10) << name;
      if (d.aspect >= 1.0) {
        EXPECT_LT(std::abs(runout), 0.25) << name;
        EXPECT_NEAR(t90 / t90_dem, 1.0, 0.25) << name;
      } else {
        EXPECT_LT(std::abs(runout), 0.30) << name;  // short: docs/fast_flows.md
        EXPECT_NEAR(t90 / t90_dem, 1.0, 0.27) << name;
      }
    }
  }
}

// Raining is what bends the run-out's growth with a: from a = 2 to 4 the
// DEM's grows as a^0.62 (Lajeunesse et al. 2004 measured a^0.5 in tubes
// past a = 1.7); with raining the grid's grows as a^0.79, while the same
// flow without it (a hydrostatic shallow layer, the failed mass flowing at
// once) turns the column's whole height into horizontal pressure and grows
// faster than a (a^1.21).
TEST(DemCollapse, RainingBendsTheRunOutsGrowthLikeTheDem) {
  const Reference& s = reference();
  double dem2 = 0.0, dem4 = 0.0;
  for (const DemColumn& d : s.dem) {
    if (!standing_tube(d)) continue;
    if (d.aspect == 2.0) dem2 = d.runout;
    if (d.aspect == 4.0) dem4 = d.runout;
  }
  ASSERT_GT(dem2, 0.0);
  ASSERT_GT(dem4, 0.0);
  const double dem_exponent = std::log(dem4 / dem2) / std::log(2.0);
  double exponents[2] = {0.0, 0.0};
  for (bool raining : {true, false}) {
    double r2 = 0.0, r4 = 0.0;
    for (const DemColumn& d : s.dem) {
      if (d.slot || d.drop_over_r0 > 0.0 || (d.aspect != 2.0 && d.aspect != 4.0)) continue;
      const auto run = terrain::run_column_collapse(dem_column_case(d, 0.1, true, raining), s.sand.flow);
      EXPECT_TRUE(run.books_exact);
      (d.aspect == 2.0 ? r2 : r4) = run.runout_over_r0;
    }
    const double exponent = std::log(r4 / r2) / std::log(2.0);
    std::printf("[ measured ] run-out from a = 2 to 4 grows as a^%.2f %s (DEM a^%.2f)\n", exponent,
                raining ? "raining" : "hydrostatic", dem_exponent);
    exponents[raining ? 0 : 1] = exponent;
  }
  EXPECT_NEAR(exponents[0], dem_exponent, 0.25) << "raining";
  EXPECT_GT(exponents[1], 1.0) << "hydrostatic";
  EXPECT_LT(exponents[0], exponents[1] - 0.25);
}

// Today's automaton alone stops the run-out 40-56 % short and stands up to
// 72 % tall (10 cm; docs/performance.md): the fast flow is closer on every
// column, and holds the tubes' mass closer to where the DEM's lies
// (mass_gap 0.03-0.07 against 0.04-0.30; the slot's, untested, 0.03
// against 0.09).
TEST(DemCollapse, TheFastFlowIsCloserThanTheAutomatonOnEveryColumn) {
  const Reference& s = reference();
  for (const DemColumn& d : s.dem) {
    if (d.drop_over_r0 > 0.0) continue;  // DroppedColumn
    const auto fast = terrain::run_column_collapse(dem_column_case(d, 0.1, true, true), s.sand.flow);
    const auto slow = terrain::run_column_collapse(dem_column_case(d, 0.1, false, false), s.sand.flow);
    EXPECT_LT(column_error(d, fast), column_error(d, slow)) << column_name(d);
    if (!d.slot) {
      EXPECT_LT(mass_gap(deposit_profile(fast), d.deposit), mass_gap(deposit_profile(slow), d.deposit)) << column_name(d);
    }
  }
}

// A load let go from a height (a = 1 dropped 4 r0, as a bucket's load dumped
// from 2 m): the DEM's grains splash out to a flat deposit, edge 1.68 r0 out
// and 0.40 r0 high. Landing with its momentum and pressing on the layer with
// its impact (dem_sand's impact_sheet_speed_ratio, measured on the DEM's
// granular jet, not on this run), the grid's heap spreads to the DEM's edge
// within 25 % (+19 / -2 % at 10 / 5 cm; a 10 cm cell is 6 % of it) and
// holds its mass where the DEM's lies, the share within every distance from
// the axis within 0.13 of the DEM's (0.125 / 0.107; with the fall lost 0.18 /
// 0.22, the automaton alone 0.36), but stands taller, within 50 % of its
// height (+29 / +31 %: its middle, where the stagnation flow under the
// landing is slow, keeps a cone holding little mass); with the fall lost at
// the impact it stays 29-38 % short and 76-79 % tall, and the automaton
// alone shorter still (docs/fast_flows.md).
TEST(DemCollapse, ADroppedColumnSpreadsWithItsImpactAsTheDemsDoes) {
  const Reference& s = reference();
  terrain::SoilFlowParameters lost = s.sand.flow;
  lost.impact_sheet_speed_ratio = 0.0;
  bool found = false;
  for (const DemColumn& d : s.dem) {
    if (d.drop_over_r0 <= 0.0) continue;
    found = true;
    for (double cell : {0.1, 0.05}) {
      const auto fast = terrain::run_column_collapse(dem_column_case(d, cell, true, true), s.sand.flow);
      const auto plain = terrain::run_column_collapse(dem_column_case(d, cell, true, true), lost);
      const auto slow = terrain::run_column_collapse(dem_column_case(d, cell, false, false), s.sand.flow);
      std::printf("[ measured ] %s, %g m: edge %.2f (DEM %.2f; the fall lost %.2f, automaton %.2f), height %.2f (DEM %.2f; "
                  "the fall lost %.2f, automaton %.2f)\n",
                  column_name(d).c_str(), cell, fast.edge_runout_over_r0, d.edge_runout, plain.edge_runout_over_r0,
                  slow.edge_runout_over_r0, fast.final_height_over_r0, d.height, plain.final_height_over_r0,
                  slow.final_height_over_r0);
      // Where each holds its mass against the DEM (the shares within every
      // distance from the axis; RunOutHeightAndFrontAgainstTheDemAtTwoCellSizes).
      const double gap = mass_gap(deposit_profile(fast), d.deposit), gap_lost = mass_gap(deposit_profile(plain), d.deposit),
                   gap_slow = mass_gap(deposit_profile(slow), d.deposit);
      std::printf("[ measured ] %s, %g m: mass gap %.3f (the fall lost %.3f, automaton %.3f)\n", column_name(d).c_str(), cell,
                  gap, gap_lost, gap_slow);
      EXPECT_LE(gap, 0.13) << cell;
      EXPECT_LT(gap, gap_lost - 0.05) << cell;
      EXPECT_TRUE(fast.books_exact && plain.books_exact && slow.books_exact) << cell;
      EXPECT_TRUE(fast.flow_at_rest && plain.flow_at_rest) << cell;
      EXPECT_NEAR(fast.edge_runout_over_r0 / d.edge_runout, 1.0, 0.25) << cell;
      EXPECT_NEAR(fast.final_height_over_r0 / d.height, 1.0, 0.5) << cell;
      EXPECT_LT(fast.final_height_over_r0, plain.final_height_over_r0 - 0.15) << cell;
      EXPECT_GT(fast.edge_runout_over_r0, plain.edge_runout_over_r0 + 0.4) << cell;
      EXPECT_GT(plain.edge_runout_over_r0, 1.3 * slow.edge_runout_over_r0) << cell;
      EXPECT_GT(plain.final_height_over_r0 / d.height, 1.7) << cell;
    }
  }
  EXPECT_TRUE(found);
}

// The sessions' sands (dry_sand, lete_sand: the shipped sand sites) take
// the sheet speed ratio the DEM's jet measured (assets/soils.xml): a bucket's
// load, a column 1 m across and 0.5 m tall (0.39 m3), dumped from 2 m (4 r0, the DEM's
// dropped column in its dimensionless form) at the sessions' 5 cm and at
// 2.5 cm, with the flow the sessions run (terrain::session_flow_parameters).
// Their own flow law (Coulomb at the stop angle, no thin-layer law) is not
// the DEM material's, so this is the dump's footprint a trainee sees, not a
// calibration: its edge within 15 % of the DEM's (dry_sand +7 / +1 %,
// lete_sand +1 / -2 %), where with the fall lost it is 17-29 % short; its
// mass where the DEM's lies within 0.12 at every distance from the axis
// (0.06-0.08; with the fall lost 0.15-0.19); its middle stands taller than
// the DEM's flat cake (+43-75 %), yet lower than with the fall lost
// (docs/fast_flows.md, "The sessions' sands").
TEST(DemCollapse, TheSessionsSandsSpreadADumpToTheDemsEdge) {
  const Reference& s = reference();
  const fs::path material_path = repository_dem_dir() / "calibration/material.csv";
  const double measured_c = read_csv_quantities(material_path).at("impact_sheet_speed_ratio");
  const auto table = io::load_soil_table(io::default_soil_table_path());
  const DemColumn* dropped = nullptr;
  for (const DemColumn& d : s.dem)
    if (d.drop_over_r0 > 0.0) dropped = &d;
  ASSERT_NE(dropped, nullptr);
  for (const char* name : {"dry_sand", "lete_sand"}) {
    const terrain::SoilFlowParameters sand = table.at(name).flow;
    EXPECT_NEAR(sand.impact_sheet_speed_ratio, measured_c, 0.005) << name;
    terrain::SoilFlowParameters lost = sand;
    lost.impact_sheet_speed_ratio = 0.0;
    for (double cell : {0.05, 0.025}) {
      terrain::CollapseCase c;
      c.aspect = dropped->aspect;
      c.r0_m = 0.5;
      c.cell_m = cell;
      c.momentum = true;
      c.drop_over_r0 = dropped->drop_over_r0;
      c.momentum_params = terrain::session_flow_parameters();  // as the sessions run it
      const auto run = terrain::run_column_collapse(c, sand), plain = terrain::run_column_collapse(c, lost);
      std::printf("[ measured ] %s, a load 1 m across dumped from %.1f m, %g m: edge %.2f r0 (DEM %.2f; the fall lost %.2f), "
                  "height %.2f r0 (DEM %.2f; the fall lost %.2f)\n",
                  name, c.drop_over_r0 * c.r0_m, cell, run.edge_runout_over_r0, dropped->edge_runout, plain.edge_runout_over_r0,
                  run.final_height_over_r0, dropped->height, plain.final_height_over_r0);
      const double gap = mass_gap(deposit_profile(run), dropped->deposit), gap_lost = mass_gap(deposit_profile(plain), dropped->deposit);
      std::printf("[ measured ] %s, a load 1 m across dumped from %.1f m, %g m: mass gap %.3f (the fall lost %.3f)\n", name,
                  c.drop_over_r0 * c.r0_m, cell, gap, gap_lost);
      EXPECT_TRUE(run.books_exact && plain.books_exact && run.flow_at_rest && plain.flow_at_rest) << name << ", " << cell;
      EXPECT_NEAR(run.edge_runout_over_r0 / dropped->edge_runout, 1.0, 0.15) << name << ", " << cell;
      EXPECT_LE(gap, 0.12) << name << ", " << cell;
      EXPECT_LT(gap, gap_lost - 0.08) << name << ", " << cell;
      EXPECT_GT(run.edge_runout_over_r0, plain.edge_runout_over_r0 + 0.3) << name << ", " << cell;
      EXPECT_LT(run.final_height_over_r0, plain.final_height_over_r0 - 0.08) << name << ", " << cell;
    }
  }
}

// A load poured from a body lands as a stream, not as a block: the DEM's
// granular jet (dem/calibration/results/impact_summary.csv), a column 0.08 m
// across and 7.2 times as long let go 0.3 m above the floor, lands in a flat
// cake 0.76 R high whose edge lies 3.8 R beyond R (and the sheet it throws
// out keeps 0.20 of its free fall's speed: dem_sand's
// impact_sheet_speed_ratio). The model, its grains scaled with the jet's
// radius R as the columns' with r0: the edge within 30 % at 10 and 20 cells
// per radius (+24 / +24 %, a 10 cm cell 3 % of it), the centre within 30 %
// (+6 / +21 %) (docs/fast_flows.md).
TEST(DemCollapse, AGranularJetLandsWhereTheDemsDid) {
  const Reference& s = reference();
  const fs::path path = repository_dem_dir() / "calibration/results/impact_summary.csv";
  const std::map<std::string, double> jet = read_csv_quantities(path);
  DemColumn d = s.dem.front();  // the deck's floor
  d.slot = false;
  d.aspect = d.released_aspect = jet.at("column_length_over_R");
  d.drop_over_r0 = jet.at("drop_m") / jet.at("jet_radius_m");
  d.grain_diameter_over_r0 = s.sand.flow.grain_diameter_m / jet.at("jet_radius_m");
  for (double cell : {0.1, 0.05}) {
    const auto run = terrain::run_column_collapse(dem_column_case(d, cell, true, true), s.sand.flow);
    const double height = run.final_state.centre_height_m / run.c.r0_m;
    std::printf("[ measured ] the jet, %g m: edge %.2f R (DEM %.2f), r99 %.2f R (DEM %.2f), height %.2f R (DEM %.2f)\n", cell,
                run.edge_runout_over_r0, jet.at("edge_runout_over_R"), run.runout_over_r0, jet.at("r99_runout_over_R"), height,
                jet.at("final_height_over_R"));
    EXPECT_TRUE(run.books_exact && run.flow_at_rest) << cell;
    EXPECT_NEAR(run.edge_runout_over_r0 / jet.at("edge_runout_over_R"), 1.0, 0.3) << cell;
    EXPECT_NEAR(height / jet.at("final_height_over_R"), 1.0, 0.3) << cell;
  }
}

// The DEM's erodible bed runs (dem/calibration/erodible.in), one row a run.
fs::path erodible_summary_path() {
  return repository_dem_dir() / "calibration/results/erodible_summary.csv";
}

// Which thickness the thin-layer law reads: the top 4, 8 or 12 grains of a
// bed 24 grains deep of the same grains at rest, set moving at 0.5, 1 or
// 1.5 m/s (dem/calibration/erodible.in, a calibration run apart from the
// columns), slow at the friction of their own thickness and stop, at 26 and
// 28 deg (at 29 and 30 deg the bed flows by itself). The law read on
// the flowing layer (the depth it moves in by default on a bed at rest
// below its start angle) gives that friction within 11 % and stops them;
// read on the grains' whole depth (LayerDepth::kWhole) it would run them
// on. The law, fit on the chute's frozen base, reads 3-10 % under
// the DEM's layers on their own bed, whose top grains, sheared along, take
// some of the layer's momentum.
TEST(DemErodibleBed, AThinLayerOnADeepBedFeelsItsOwnThickness) {
  const Reference& s = reference();
  const fs::path path = erodible_summary_path();
  const CsvNumbers dem = read_csv_numbers(path);
  const std::size_t layers = dem.column("layers", path), top = dem.column("top_layers", path),
                    theta = dem.column("theta_deg", path), mu_top = dem.column("mu_top", path),
                    stops = dem.column("stopped", path);
  terrain::GridSpec spec;
  spec.nx = spec.ny = 4;
  const terrain::GranularGrid grid(spec, s.sand.flow, 0.002);
  const terrain::MomentumFlow flow(grid, terrain::MomentumFlowParameters{}, 0.002);
  const double grain_m = s.sand.flow.grain_diameter_m;
  int stopped = 0;
  for (const std::vector<double>& row : dem.rows) {
    if (row[stops] != 1.0) continue;
    ++stopped;
    const double theta_deg = row[theta], mu_dem = row[mu_top];
    // The top grains are the bed's own top: its whole depth is `layers`.
    const double top_m = row[top] * grain_m, whole_m = row[layers] * grain_m;
    const double tan_theta = std::tan(deg_to_rad(theta_deg));
    std::printf("[ measured ] %g deg: the DEM's layer of %.0f grains slowed at mu %.3f; the law at its own thickness %.3f, "
                "at the whole %.0f grains %.3f\n", theta_deg, row[top], mu_dem, flow.bed_friction_tan(top_m), row[layers],
                flow.bed_friction_tan(whole_m));
    EXPECT_NEAR(flow.bed_friction_tan(top_m) / mu_dem, 1.0, 0.11) << theta_deg << " deg, " << row[top] << " grains";
    EXPECT_GT(flow.bed_friction_tan(top_m), tan_theta) << theta_deg << " deg, " << row[top] << " grains: the layer stops";
    EXPECT_LT(flow.bed_friction_tan(whole_m), tan_theta) << theta_deg << " deg: read on the whole depth it would run on";
  }
  EXPECT_EQ(stopped, 5) << "every run but those whose bed flowed by itself";
}

// The DEM's erodible bed in the model: a bed 24 grains deep (0.192 m of
// dem_sand) on a base tilted to the DEM's angle, running onto a level bed,
// with the DEM's layer (its top grains, at its speed) set moving on its top
// 0.2 m, at 2 and 5 cm cells. Where the DEM's bed held (26 and 28 deg,
// below its start angle, 28.5 deg), the model cuts none of it: the layer
// carries away only what it laid down. Without the start angle every bed
// under a moving layer erodes to the flowing friction (23.7 deg), and at 28
// deg the model cut the bed the DEM kept.
double model_bed_cut_m3(io::SoilRecord soil, double theta_deg, double top_grains, double v0_m_s, double cell_m) {
  const double grain_m = soil.flow.grain_diameter_m, bed_m = 24 * grain_m, layer_m = top_grains * grain_m;
  terrain::GridSpec spec;
  spec.nx = static_cast<int>(std::lround(4.0 / cell_m));
  spec.ny = 1;
  spec.cell_size_m = cell_m;
  terrain::GranularGrid g(spec, soil.flow, 0.002, 100000);
  const int ramp = static_cast<int>(std::lround(2.4 / cell_m));
  const double tan_theta = std::tan(deg_to_rad(theta_deg));
  std::vector<double> before(static_cast<std::size_t>(spec.nx));
  for (int i = 0; i < spec.nx; ++i) {
    g.set_base_m(i, 0, std::max(0, ramp - i) * cell_m * tan_theta);
    g.set_material_m(i, 0, bed_m);
    before[static_cast<std::size_t>(i)] = g.material_m(i, 0);
  }
  terrain::MomentumFlow flow(g, terrain::MomentumFlowParameters{}, 0.002);
  for (int i = 0; i * cell_m < 0.2; ++i) {
    g.add_material_m3(i, 0, layer_m * cell_m * cell_m);
    flow.land(g, g.index(i, 0), std::llround(layer_m / terrain::kHeightQuantumM), v0_m_s * std::cos(deg_to_rad(theta_deg)), 0.0);
  }
  for (int step = 0; step < 20000 && (step == 0 || flow.moving_cells() > 0); ++step) flow.step(g);
  EXPECT_EQ(flow.moving_cells(), 0u);
  double cut_m3 = 0.0;
  for (int i = 0; i < spec.nx; ++i)
    cut_m3 += std::max(0.0, before[static_cast<std::size_t>(i)] - g.material_m(i, 0)) * cell_m * cell_m;
  return cut_m3;
}

TEST(DemErodibleBed, TheModelKeepsTheBedTheDemKept) {
  const Reference& s = reference();
  const fs::path path = erodible_summary_path();
  const CsvNumbers dem = read_csv_numbers(path);
  const std::size_t top = dem.column("top_layers", path), theta = dem.column("theta_deg", path),
                    v0 = dem.column("v0_m_s", path), stops = dem.column("stopped", path),
                    bed_travel = dem.column("bed_travel_m", path);
  io::SoilRecord without = s.sand;
  without.flow.bed_start_angle_deg = 0.0;
  int held = 0;
  for (const std::vector<double>& row : dem.rows) {
    if (row[stops] != 1.0) continue;
    ++held;
    EXPECT_LT(row[theta], s.sand.flow.bed_start_angle_deg);
    for (double cell : {0.05, 0.02}) {
      const double layer_m3 = 0.2 * row[top] * s.sand.flow.grain_diameter_m * cell;  // the layer's volume on the strip
      const double cut = model_bed_cut_m3(s.sand, row[theta], row[top], row[v0], cell);
      const double cut_without = model_bed_cut_m3(without, row[theta], row[top], row[v0], cell);
      std::printf("[ measured ] %g deg, %.0f grains at %g m/s, %.2f m cells: the DEM's bed sheared along (its grains' mean "
                  "travel %.3f m) and held; the model cut %.5f m3 of it (%.5f m3 without the bed's start angle; the layer "
                  "%.5f m3)\n", row[theta], row[top], row[v0], cell, row[bed_travel], cut, cut_without, layer_m3);
      EXPECT_LT(cut, 0.01 * layer_m3) << row[theta] << " deg, " << row[top] << " grains, " << cell << " m";
      if (row[theta] == 28.0 && row[top] == 8.0) {
        EXPECT_GT(cut_without, layer_m3) << cell << " m";
      }
    }
  }
  EXPECT_EQ(held, 5);
}

}  // namespace
}  // namespace skidsim::report::perf
