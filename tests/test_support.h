// Small helpers shared by the terrain tests.
#pragma once

#include <cmath>
#include <memory>

#include "terrain/granular_grid.h"

namespace skidsim::terrain::testing {

inline constexpr double kPi = 3.14159265358979323846;
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

// Largest slope angle (deg) anywhere on the surface, by the automaton's own
// isotropic slope measure (steepest downhill difference on each axis).
inline double max_slope_deg(const GranularGrid& g) {
  double worst = 0.0;
  for (int j = 0; j < g.ny(); ++j) {
    for (int i = 0; i < g.nx(); ++i) {
      if (g.material_quanta(i, j) == 0) continue;
      const double h = g.surface_m(i, j);
      const auto drop = [&](int a, int b) { return g.contains(a, b) ? std::max(0.0, h - g.surface_m(a, b)) : 0.0; };
      const double sx = std::max(drop(i + 1, j), drop(i - 1, j)) / g.cell_size_m();
      const double sy = std::max(drop(i, j + 1), drop(i, j - 1)) / g.cell_size_m();
      worst = std::max(worst, std::atan(std::hypot(sx, sy)) * 180.0 / kPi);
    }
  }
  return worst;
}

}  // namespace skidsim::terrain::testing
