// The fast flow's cells and faces (terrain/momentum_flow.h), shared by its
// translation units: directions, a neighbour or what lies beyond the grid,
// and whether a face's velocity leaves a cell.
#pragma once

#include "terrain/granular_grid.h"

namespace skidsim::terrain::momentum_cells {

// Directions +x, -x, +y, -y as (di, dj), and the grid edge each crosses.
constexpr int kDi[4] = {1, -1, 0, 0};
constexpr int kDj[4] = {0, 0, 1, -1};
constexpr Edge kEdgeOf[4] = {kEdgeXMax, kEdgeXMin, kEdgeYMax, kEdgeYMin};

// Cell (i, j)'s index; beyond the grid (across `edge`) -1 for an open edge
// (a drop-off) and -2 for a closed one; -2 for a covered cell (a wall).
inline int cell_or_edge(const GranularGrid& g, int i, int j, Edge edge) {
  if (!g.contains(i, j)) return g.spec().edges[edge] == EdgeKind::kOpen ? -1 : -2;
  const int c = g.index(i, j);
  return g.covered(c) ? -2 : c;
}

// The neighbour of (i, j) towards direction k, as cell_or_edge.
inline int neighbour(const GranularGrid& g, int i, int j, int k) { return cell_or_edge(g, i + kDi[k], j + kDj[k], kEdgeOf[k]); }

// Whether velocity u across a cell's face towards direction k leaves the cell.
inline bool leaves(int k, double u) { return k % 2 == 0 ? u > 0.0 : u < 0.0; }

}  // namespace skidsim::terrain::momentum_cells
