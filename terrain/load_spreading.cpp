#include "terrain/load_spreading.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace skidsim::terrain {
namespace {

// One axis of the kernel, "send" form: each cell passes eps of its load to
// each neighbour along the axis and keeps the rest; a neighbour beyond the
// grid does not exist, so that share stays. Sums are preserved.
void spread_axis(const double* in, double* out, int n, int stride, int count, int count_stride, double eps) {
  for (int k = 0; k < count; ++k) {
    const double* a = in + static_cast<std::ptrdiff_t>(k) * count_stride;
    double* b = out + static_cast<std::ptrdiff_t>(k) * count_stride;
    for (int i = 0; i < n; ++i) b[static_cast<std::ptrdiff_t>(i) * stride] = 0.0;
    for (int i = 0; i < n; ++i) {
      const double p = a[static_cast<std::ptrdiff_t>(i) * stride];
      if (p == 0.0) continue;
      const double side = eps * p;
      double keep = p - 2.0 * side;
      if (i > 0) b[static_cast<std::ptrdiff_t>(i - 1) * stride] += side; else keep += side;
      if (i + 1 < n) b[static_cast<std::ptrdiff_t>(i + 1) * stride] += side; else keep += side;
      b[static_cast<std::ptrdiff_t>(i) * stride] += keep;
    }
  }
}

}  // namespace

void validate(const LoadSpreading& s) {
  if (!(s.eps >= 0.0 && s.eps <= 0.5)) {
    std::ostringstream msg;
    msg << "load spreading: eps = " << s.eps << " (expected in [0, 0.5]; the thesis recommends 1/3 to 1/2)";
    throw std::invalid_argument(msg.str());
  }
  if (!(s.block_height_cells >= 0.25 && s.block_height_cells <= 8.0)) {
    std::ostringstream msg;
    msg << "load spreading: block_height_cells = " << s.block_height_cells
        << " (expected in [0.25, 8]; 1 to 2 spreads the load 30-45 deg from the vertical)";
    throw std::invalid_argument(msg.str());
  }
}

void base_loads_N(const GranularGrid& grid, const LoadSpreading& spreading, double gravity_m_s2,
                  std::vector<double>* loads, LoadSpreadingScratch* scratch) {
  const int nx = grid.nx(), ny = grid.ny();
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  const double d = grid.cell_size_m();
  const double block_m = spreading.block_height_cells * d;
  const double weight_per_m = grid.soil().bulk_density_kg_m3 * gravity_m_s2 * d * d;  // N per metre of column
  double tallest = 0.0;
  for (int c = 0; c < static_cast<int>(n); ++c) tallest = std::max(tallest, grid.loose_quanta(c) * kHeightQuantumM);
  loads->assign(n, 0.0);
  if (tallest <= 0.0) return;
  std::vector<double>& above = scratch->above;
  std::vector<double>& here = scratch->here;
  std::vector<double>& row = scratch->row;
  above.assign(n, 0.0);
  here.resize(n);
  row.resize(n);
  const int layers = static_cast<int>(std::ceil(tallest / block_m));
  // From the top layer down: p^n = m^n + spread(p^{n+1}).
  for (int layer = layers - 1; layer >= 0; --layer) {
    // spread(p^{n+1}): along x for every row, then along y for every column.
    spread_axis(above.data(), row.data(), nx, 1, ny, nx, spreading.eps);
    spread_axis(row.data(), here.data(), ny, nx, nx, 1, spreading.eps);
    const double bottom = layer * block_m;
    for (int c = 0; c < static_cast<int>(n); ++c) {
      const double column = grid.loose_quanta(c) * kHeightQuantumM;
      const double in_block = std::clamp(column - bottom, 0.0, block_m);
      here[static_cast<std::size_t>(c)] += weight_per_m * in_block;
    }
    above.swap(here);
  }
  *loads = above;
}

}  // namespace skidsim::terrain
