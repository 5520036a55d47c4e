// Small helpers shared by the terrain tests.
#pragma once

#include <cmath>
#include <memory>
#include <vector>
#include <algorithm>

#include "common/physical_constants.h"
#include "terrain/granular_grid.h"

namespace skidsim::terrain::testing {

inline constexpr double kDt = 0.002;

inline GridSpec square_spec(int n, double cell_m, EdgeKind edges = EdgeKind::kClosed) {
  GridSpec spec;
  spec.nx = spec.ny = n;
  spec.cell_size_m = cell_m;
  spec.edges.fill(edges);
  return spec;
}

// Steps until the terrain is at rest; returns the steps taken (or -1 when
// `max_steps` did not suffice).
inline long settle(GranularGrid& g, long max_steps) {
  for (long s = 0; s < max_steps; ++s) {
    if (g.at_rest()) return s;
    g.step();
  }
  return g.at_rest() ? max_steps : -1;
}

// At rest a face can lean past the repose angle only where its drop is too
// small for any flow to round to a whole quantum (sub-micrometre drops beside
// a steep tangential slope, e.g. along a wall): 0.1 deg covers it.
inline constexpr double kRestSlopeToleranceDeg = 0.1;

// Largest slope angle (deg) down which any cell could send material, by the
// automaton's own slope measure.
inline double max_slope_deg(const GranularGrid& g) {
  double worst = 0.0;
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i) worst = std::max(worst, g.downhill_slope_tan(i, j));
  return std::atan(worst) * 180.0 / kPi;
}

// Median slope angle (deg) of a pile's flank: the cells whose material is
// between a fifth and four fifths of the pile's peak. One steep cell does
// not make a flank.
inline double median_flank_slope_deg(const GranularGrid& g) {
  double peak = 0.0;
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i) peak = std::max(peak, g.material_m(i, j));
  std::vector<double> slopes;
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i) {
      const double h = g.material_m(i, j);
      if (h > 0.2 * peak && h < 0.8 * peak) slopes.push_back(std::atan(g.downhill_slope_tan(i, j)) * 180.0 / kPi);
    }
  if (slopes.empty()) return 0.0;
  std::nth_element(slopes.begin(), slopes.begin() + slopes.size() / 2, slopes.end());
  return slopes[slopes.size() / 2];
}

}  // namespace skidsim::terrain::testing
