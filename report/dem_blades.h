// The DEM reference's blade runs (dem/blade/results, scripts/dem_reference.sh)
// and skidsim's push of the same case, in the dimensionless form both are
// compared in: N = F / (gamma d^2 w) against d/w, rake and travel over d.
// Used by `skidsim bench report` (perf_digging.cpp) and its tests.
#pragma once

#include <filesystem>
#include <utility>
#include <vector>

namespace skidsim::report::perf {

// One LIGGGHTS blade run: dem/blade/results/summary.csv and heap_summary.csv.
struct DemBlade {
  double rake_deg = 0.0, depth_m = 0.0, width_m = 0.0, density_kg_m3 = 0.0;
  double n_peak = 0.0, n_mean = 0.0, mean_from_m = 0.0, travel_m = 0.0;
  double up_over_draft = 0.0;  // the mean vertical force (up) over the mean draft
  double heap_front_d2 = -1.0;  // soil heaped ahead of the blade after 1.5 d, over w d^2 (-1: not measured)
  double heap_on_face_d2 = 0.0;  // and riding on a raked face
};

// The runs in `dir` (dem/blade/results); throws std::runtime_error naming
// the file and column when one is missing or short.
std::vector<DemBlade> read_dem_blades(const std::filesystem::path& dir);

// The DEM's draft along the travel: (travel / d, N).
std::vector<std::pair<double, double>> dem_n_along(const std::filesystem::path& dir, const DemBlade& dem);

// skidsim's push of a 1 m blade through dem_sand at the case's d/w and
// rake, over the same travel over d, run in `work`.
struct PushResult {
  double n_equation = 0.0, n_mean = 0.0, cost = 0.0;  // N: the equation's on flat ground, the mean over the DEM's window
  double up_over_draft_equation = 0.0, up_over_draft = 0.0;  // the face's vertical force (up) over the draft
  double heap_d2 = 0.0;  // the wedge's soil above flat ground after 1.5 d, over w d^2
  std::vector<std::pair<double, double>> n_along;  // (travel / d, N) every 2 cm
};
PushResult push_like(const DemBlade& dem, double cells_per_m, const std::filesystem::path& work);

}  // namespace skidsim::report::perf
