// Collapsing columns at the grain sizes of a laboratory and of a session
// (hundreds of grains per radius, r0 = 1 m) against the published run-out
// law for axisymmetric collapses (terrain::published_runout_over_r0, Lube et
// al. 2004; Lajeunesse, Mangeney-Castelnau and Vilotte 2004 found the same
// forms): independent of the DEM, whose columns hold 12.5 and 25 grains per
// radius (dem_collapse_reference_test.cpp). docs/fast_flows.md, "Where it
// stands".
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "experiments/column_collapse.h"
#include "io/soil_table.h"

namespace skidsim::terrain {
namespace {

constexpr double kAspects[] = {0.5, 1.0, 2.0, 4.0};

// dem_sand with its grains at their own size (8 mm at r0 = 1 m: 125 grains
// per radius, as in the laboratory columns, so the thin-layer law acts only
// in layers a few centimetres thick) and one friction on floor and bed.
// Within 10 % at a = 1, 2 and 4; a = 0.5, whose run-out is the edge wedge's
// slide, within 20 % (11-14 % short).
TEST(PublishedCollapseLaws, TheDemMaterialAtTheLaboratorysGrainSize) {
  const SoilFlowParameters sand = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  for (double cell : {0.1, 0.05}) {
    for (double a : kAspects) {
      const CollapseRun run = run_column_collapse(laboratory_column_case(a, cell), sand);
      const double law = published_runout_over_r0(a), error = run.runout_over_r0 / law - 1.0;
      std::printf("[ measured ] dem_sand, a = %g at %g m, 125 grains per radius: run-out %.2f r0 (published law %.2f, "
                  "%+.1f %%), height %.2f r0\n",
                  a, cell, run.runout_over_r0, law, 100.0 * error, run.final_height_over_r0);
      EXPECT_TRUE(run.books_exact);
      EXPECT_LT(std::abs(error), a < 1.0 ? 0.20 : 0.10) << "a = " << a << ", " << cell << " m";
    }
  }
}

// The sessions' sands (dry_sand, lete_sand: the shipped sand sites) in the
// same columns: what a trainee sees when a bank or a heaped load gives way.
// Their flow law is Coulomb at their stop angle (30 and 32 deg; no
// flowing_friction_angle_deg of their own, no thin-layer law), steeper than
// the DEM material's measured flowing friction (23.7 deg), and their columns
// run out short of the published law: 15-38 % (dry_sand) and 21-44 %
// (lete_sand) at 10 and 5 cm, a = 4 best and a = 0.5 worst, where the
// automaton alone runs 45-56 % short. The gap follows the flowing friction
// (at 23.7 deg dry_sand's columns come within 13 % of the law, a diagnosis
// only, which the sands' dumps against the DEM's dropped column pull the
// other way); whether it is the sands' or the model's is open
// (docs/fast_flows.md, "Where it stands"). This test holds what is reached.
TEST(PublishedCollapseLaws, TheSessionsSandsRunOutShortOfThePublishedLaw) {
  const auto table = io::load_soil_table(io::default_soil_table_path());
  for (const char* name : {"dry_sand", "lete_sand"}) {
    const SoilFlowParameters sand = table.at(name).flow;
    for (double cell : {0.1, 0.05}) {
      double last = 0.0;
      for (double a : kAspects) {
        CollapseCase c = laboratory_column_case(a, cell);
        const CollapseRun run = run_column_collapse(c, sand);
        c.momentum = false;
        const CollapseRun slow = run_column_collapse(c, sand);
        const double law = published_runout_over_r0(a), error = run.runout_over_r0 / law - 1.0,
                     slow_error = slow.runout_over_r0 / law - 1.0;
        std::printf("[ measured ] %s, a = %g at %g m: run-out %.2f r0 (published law %.2f, %+.1f %%; the automaton alone "
                    "%.2f, %+.1f %%), height %.2f r0 (the automaton alone %.2f)\n",
                    name, a, cell, run.runout_over_r0, law, 100.0 * error, slow.runout_over_r0, 100.0 * slow_error,
                    run.final_height_over_r0, slow.final_height_over_r0);
        const std::string where = std::string(name) + ", a = " + std::to_string(a) + ", " + std::to_string(cell) + " m";
        EXPECT_TRUE(run.books_exact && slow.books_exact && run.flow_at_rest) << where;
        EXPECT_LT(error, 0.0) << where;
        EXPECT_GT(error, a < 1.0 ? -0.45 : -0.36) << where;
        EXPECT_GT(error, slow_error + 0.05) << where;  // the fast flow narrows the gap
        EXPECT_GT(run.runout_over_r0, last) << where;  // and runs farther from higher columns
        last = run.runout_over_r0;
      }
    }
  }
}

}  // namespace
}  // namespace skidsim::terrain
