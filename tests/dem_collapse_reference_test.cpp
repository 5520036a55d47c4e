// skidsim's collapsing columns against the stored LIGGGHTS columns
// (dem/collapse/results; scripts/dem_reference.sh): the fast-flow prototype
// (terrain/momentum_flow.h) in dem_sand, whose repose and stop angles come
// from the DEM's pile and never from these runs, at the sessions' 10 and
// 5 cm cells (10 and 20 per radius), in run-out and final height over r0 and
// the front's arrival over sqrt(H0 / g) (report/dem_columns.h).
//
// The bounds hold what is reached (docs/terrain_model.md, "Fast flows with
// momentum"): the tubes' run-out 15-25 % short, heights within 15 %, the slot
// running out 20-30 % long; the aim of 15 % is not reached on the
// run-out. A change that loses ground fails; tighten them as the model improves.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "io/soil_table.h"
#include "report/dem_columns.h"

namespace skidsim::report::perf {
namespace {

namespace fs = std::filesystem;

struct Reference {
  std::vector<DemColumn> dem;
  io::SoilRecord sand;
};

const Reference& reference() {
  static const Reference s{read_dem_columns(fs::path(io::default_assets_dir()).parent_path() / "dem" / "collapse" / "results"),
                       io::load_soil_table(io::default_soil_table_path()).at("dem_sand")};
  return s;
}

TEST(DemCollapse, RunOutHeightAndFrontAgainstTheDemAtTwoCellSizes) {
  const Reference& s = reference();
  ASSERT_EQ(s.dem.size(), 5u);
  for (double cell : {0.1, 0.05}) {
    for (const DemColumn& d : s.dem) {
      const terrain::CollapseRun run =
          terrain::run_column_collapse(dem_column_case(d, cell, true, true, s.sand.terramechanics), s.sand.flow);
      const std::string name = std::string(d.slot ? "slot" : "tube") + " a " + std::to_string(d.aspect) + ", " +
                               std::to_string(cell) + " m";
      EXPECT_TRUE(run.books_exact) << name;
      EXPECT_TRUE(run.at_rest) << name;
      const double runout = run.runout_over_r0 / d.runout - 1.0, height = run.final_height_over_r0 / d.height - 1.0;
      if (d.slot) {
        EXPECT_GT(runout, 0.0) << name;
        EXPECT_LT(runout, 0.35) << name;
      } else {
        EXPECT_LT(std::abs(runout), 0.25) << name << ": run-out " << run.runout_over_r0 << " against " << d.runout;
      }
      EXPECT_LT(std::abs(height), 0.15) << name << ": height " << run.final_height_over_r0 << " against " << d.height;
      // The front's arrival at 90 % of its advance, within 20 % where the
      // column falls (a >= 1); the low column's edge wedge slides out
      // sooner than the DEM's.
      const double t90 = front_arrival(scaled_front(run), 0.9), t90_dem = front_arrival(d.front, 0.9);
      if (d.aspect >= 1.0) {
        EXPECT_NEAR(t90 / t90_dem, 1.0, 0.2) << name << ": t90 " << t90 << " against " << t90_dem;
      }
    }
  }
}

// Raining is what keeps tall columns from over-running: the same flow
// without it (a hydrostatic shallow layer, the failed mass flowing at once)
// turns the column's height into horizontal pressure and runs out far past
// the DEM at a = 4, while the low column, which hardly falls, runs out alike.
TEST(DemCollapse, WithoutRainingATallColumnOverRuns) {
  const Reference& s = reference();
  for (const DemColumn& d : s.dem) {
    if (d.slot || (d.aspect != 4.0 && d.aspect != 0.5)) continue;
    const auto rain = terrain::run_column_collapse(dem_column_case(d, 0.1, true, true, s.sand.terramechanics), s.sand.flow);
    const auto dry = terrain::run_column_collapse(dem_column_case(d, 0.1, true, false, s.sand.terramechanics), s.sand.flow);
    EXPECT_TRUE(dry.books_exact);
    if (d.aspect == 4.0) {
      EXPECT_GT(dry.runout_over_r0, 1.4 * d.runout);
    } else {
      EXPECT_NEAR(dry.runout_over_r0 / rain.runout_over_r0, 1.0, 0.3);
    }
  }
}

// Today's automaton alone stops the run-out a third to a half short and
// stands tall: the prototype is closer on every column.
TEST(DemCollapse, ThePrototypeIsCloserThanTheAutomatonOnEveryColumn) {
  const Reference& s = reference();
  for (const DemColumn& d : s.dem) {
    const auto fast = terrain::run_column_collapse(dem_column_case(d, 0.1, true, true, s.sand.terramechanics), s.sand.flow);
    const auto slow = terrain::run_column_collapse(dem_column_case(d, 0.1, false, false, s.sand.terramechanics), s.sand.flow);
    const auto error = [&](const terrain::CollapseRun& r) {
      return std::max(std::abs(r.runout_over_r0 / d.runout - 1.0), std::abs(r.final_height_over_r0 / d.height - 1.0));
    };
    EXPECT_LT(error(fast), error(slow)) << (d.slot ? "slot" : "tube") << " a " << d.aspect;
  }
}

}  // namespace
}  // namespace skidsim::report::perf
