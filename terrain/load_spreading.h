// The load a granular pile puts on the base under it (thesis 6.5, 7.3.3):
// not the column above each cell, because grains pass load sideways. The
// material over a cell is cut into blocks of height H; a block carries its
// own weight plus a share of the three (in 2-D, nine) blocks above it,
//   p_i^n = m_i^n + sum_k phi(k) p_{i+k}^{n+1}            (6.5)
// with phi(-1) = phi(1) = eps, phi(0) = 1 - 2 eps (per axis; the 2-D kernel
// is the product of the two, 6.10), so the load spreads at atan(d / H) from
// the vertical. Loads that would pass beyond the grid's edge stay in the edge
// cell: the base loads sum to the pile's weight, to round-off.
#pragma once

#include <vector>

#include "terrain/granular_grid.h"

namespace skidsim::terrain {

struct LoadSpreading {
  // Share passed to each side neighbour per layer; the thesis recommends
  // 1/3 < eps < 1/2 (most of the load goes sideways, Geng et al. 2001).
  double eps = 0.4;
  // Block height H in cells: d < H < 2 d spreads the load 30-45 deg from the
  // vertical (Liffman et al. 2001).
  double block_height_cells = 1.5;
};

// Throws std::invalid_argument naming the field (eps in [0, 1/2], block
// height in [0.25, 8] cells).
void validate(const LoadSpreading& spreading);

// Reusable buffers (sized by the grid on first use, then no allocation).
struct LoadSpreadingScratch {
  std::vector<double> above, here, row;
};

// Base load (N, along the grid's z' axis, gravity g) under every cell of
// `grid`, from its loose material. `loads` is resized to the grid.
void base_loads_N(const GranularGrid& grid, const LoadSpreading& spreading, double gravity_m_s2,
                  std::vector<double>* loads, LoadSpreadingScratch* scratch);

}  // namespace skidsim::terrain
