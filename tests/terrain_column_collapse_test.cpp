// The collapsing-column experiment (experiments/column_collapse.h) that the
// performance report sets beside the DEM's columns: its books, its measures,
// and the one outcome of a low column that holds whatever the flow law
// (Lajeunesse et al. 2004, Lube et al. 2004): below a ~ 0.7 the column's top
// is never reached by the failure, so the centre keeps its height H0.
#include <gtest/gtest.h>

#include "experiments/column_collapse.h"

namespace skidsim::terrain {
namespace {

TEST(ColumnCollapse, ALowColumnKeepsItsTopAndSpreadsWithExactBooks) {
  CollapseCase c;
  c.aspect = 0.5;
  c.cell_m = 0.1;
  const CollapseRun run = run_column_collapse(c, SoilFlowParameters{});
  EXPECT_TRUE(run.books_exact);
  EXPECT_NEAR(run.final_height_over_r0, c.aspect, 1e-12);
  EXPECT_GT(run.runout_over_r0, 0.1);
  // The front only advances; the measures start from the column as released.
  ASSERT_GE(run.frames.size(), 3u);
  EXPECT_NEAR(run.frames.front().front_edge_m, c.r0_m, c.cell_m);
  for (std::size_t k = 1; k < run.frames.size(); ++k)
    EXPECT_GE(run.frames[k].front_r99_m, run.frames[k - 1].front_r99_m - 1e-9) << "frame " << k;
}

TEST(ColumnCollapse, TheSlotSpreadsOneWayAndTheTubeEveryWay) {
  CollapseCase tube, slot;
  tube.aspect = slot.aspect = 2.0;
  tube.cell_m = slot.cell_m = 0.1;
  slot.slot = true;
  const CollapseRun t = run_column_collapse(tube, SoilFlowParameters{});
  const CollapseRun s = run_column_collapse(slot, SoilFlowParameters{});
  EXPECT_TRUE(t.books_exact && s.books_exact);
  // The same volume per unit of front spreads over a line in the slot and
  // over a disc in the tube: the slot's deposit reaches farther and stands
  // taller at the wall than the tube's at its axis.
  EXPECT_GT(s.runout_over_r0, t.runout_over_r0);
  EXPECT_GT(s.final_height_over_r0, t.final_height_over_r0);
  EXPECT_LT(t.final_height_over_r0, tube.aspect);
  CollapseCase coarse;
  coarse.cell_m = 2.0;  // cells wider than the column
  EXPECT_THROW(run_column_collapse(coarse, SoilFlowParameters{}), std::invalid_argument);
}

}  // namespace
}  // namespace skidsim::terrain
