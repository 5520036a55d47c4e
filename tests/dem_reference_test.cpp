// skidsim against the stored LIGGGHTS blade runs (dem/blade/results; the
// DEM material calibrated apart from them, dem/README.md): a 1 m blade
// pushed through dem_sand at each run's d/w, rake and travel over d, at 10
// and 20 cells/m, in N = F / (gamma d^2 w) (report/dem_blades.h).
//
// What is reached, not the issue's 15 % (docs/soil_contact.md, "Against the
// DEM reference"): skidsim meets the earthmoving equation, and the equation
// overestimates this DEM's vertical blade (1.6-2.1 times, given the DEM's
// own heap) while meeting its raked one within about 10 %. These bounds
// hold what is reached so that a change that loses it fails; tighten them
// as the model improves.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include <unistd.h>

#include "report/dem_blades.h"
#include "report/perf_report_parts.h"

namespace skidsim::report::perf {
namespace {

namespace fs = std::filesystem;

fs::path dem_results() { return repository_dem_dir() / "blade" / "results"; }

class DemBladeCellSizes : public ::testing::TestWithParam<double> {};

TEST_P(DemBladeCellSizes, PushAgainstTheStoredDemRuns) {
  const std::vector<DemBlade> runs = read_dem_blades(dem_results());
  ASSERT_EQ(runs.size(), 4u);
  const fs::path work = fs::temp_directory_path() / ("skidsim_dem_reference_" + std::to_string(::getpid()));
  for (const DemBlade& dem : runs) {
    const PushResult r = push_like(dem, GetParam(), work);
    const double ratio = r.n_mean / dem.n_mean;
    const double heap_dem = dem.heap_front_d2 + dem.heap_on_face_d2;
    std::printf("[ measured ] %g deg, d/w %.1f, %.0f cells/m: N mean %.2f (DEM %.2f, x%.2f); V/H %+.2f (DEM %+.2f); "
                "heap %.2f d^2 (DEM %.2f)\n",
                dem.rake_deg, dem.depth_m / dem.width_m, GetParam(), r.n_mean, dem.n_mean, ratio, r.up_over_draft,
                dem.up_over_draft, r.heap_d2, heap_dem);
    // The draft along the push: over the DEM's mean, at most 1.5 times for
    // the raked blade (measured 1.20-1.41) and 2.5 times for the vertical one
    // (measured 1.87-2.20).
    EXPECT_GT(ratio, 1.0);
    EXPECT_LT(ratio, dem.rake_deg < 89.0 ? 1.5 : 2.5);
    // The face's vertical force over the draft: the DEM's sign (up for the
    // vertical blade, down for the raked one), within 0.1 (measured 0.05-0.08).
    EXPECT_GT(r.up_over_draft * dem.up_over_draft, 0.0);
    EXPECT_NEAR(r.up_over_draft, dem.up_over_draft, 0.1);
    // The heap after 1.5 d: the DEM's in front and on a raked face (a 2.5-D
    // grid holds none on the face), within 50 % (measured -7 to +45 %).
    EXPECT_NEAR(r.heap_d2, heap_dem, 0.5 * heap_dem);
  }
  fs::remove_all(work);
}

INSTANTIATE_TEST_SUITE_P(TwoCellSizes, DemBladeCellSizes, ::testing::Values(10.0, 20.0));

}  // namespace
}  // namespace skidsim::report::perf
