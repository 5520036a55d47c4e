#include "terrain/pile_metrics.h"
#include "common/physical_constants.h"

#include <cmath>

namespace skidsim::terrain {
namespace {


// Walks from the centre along (di, dj) and returns the distance at which the
// material height crosses `edge_m`, linearly interpolated.
double run_out(const GranularGrid& grid, int ci, int cj, int di, int dj, double edge_m) {
  const double step_m = grid.cell_size_m() * std::sqrt(double(di * di + dj * dj));
  double prev = grid.material_m(ci, cj);
  for (int k = 1;; ++k) {
    const int i = ci + k * di, j = cj + k * dj;
    if (!grid.contains(i, j)) return (k - 1) * step_m;
    const double h = grid.material_m(i, j);
    if (h <= edge_m) {
      const double t = prev > h ? (prev - edge_m) / (prev - h) : 0.0;
      return (k - 1 + t) * step_m;
    }
    prev = h;
  }
}

}  // namespace

PileMetrics measure_pile(const GranularGrid& grid, int ci, int cj, double edge_material_m) {
  PileMetrics m;
  m.apex_material_m = grid.material_m(ci, cj);
  const int axes[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  const int diagonals[4][2] = {{1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
  for (const auto& a : axes) m.radius_axes_m += 0.25 * run_out(grid, ci, cj, a[0], a[1], edge_material_m);
  for (const auto& a : diagonals) m.radius_diagonals_m += 0.25 * run_out(grid, ci, cj, a[0], a[1], edge_material_m);

  // h = a - s r over the flank: least squares for s.
  double sr = 0, sh = 0, srr = 0, srh = 0;
  const double lo = 0.15 * m.apex_material_m, hi = 0.85 * m.apex_material_m;
  for (int j = 0; j < grid.ny(); ++j) {
    for (int i = 0; i < grid.nx(); ++i) {
      const double h = grid.material_m(i, j);
      if (h < lo || h > hi) continue;
      const double r = grid.cell_size_m() * std::hypot(double(i - ci), double(j - cj));
      sr += r; sh += h; srr += r * r; srh += r * h;
      ++m.flank_cells;
    }
  }
  if (m.flank_cells >= 2) {
    const double n = m.flank_cells;
    const double slope = -(n * srh - sr * sh) / (n * srr - sr * sr);
    m.flank_slope_deg = std::atan(slope) * 180.0 / kPi;
  }
  return m;
}

}  // namespace skidsim::terrain
