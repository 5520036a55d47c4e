#include "session/terrain_tiles.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace skidsim::session {

TerrainTiles::TerrainTiles(const terrain::GranularGrid& grid)
    : tiles_x_((grid.nx() + kTileCells - 1) / kTileCells),
      tiles_y_((grid.ny() + kTileCells - 1) / kTileCells),
      sent_m_(static_cast<std::size_t>(grid.nx()) * grid.ny(), std::numeric_limits<float>::quiet_NaN()) {
  tile_.cell_m = grid.cell_size_m();
  tile_.origin_m[0] = grid.spec().origin_m.x();
  tile_.origin_m[1] = grid.spec().origin_m.y();
  tile_.grid_nx = grid.nx();
  tile_.grid_ny = grid.ny();
  tile_.surface_m.reserve(kTileCells * kTileCells);
}

bool TerrainTiles::fill_if_changed(const terrain::GranularGrid& grid, int ti, int tj, long step, double sim_time_s) {
  const int i0 = ti * kTileCells, j0 = tj * kTileCells;
  const int ni = std::min(kTileCells, grid.nx() - i0), nj = std::min(kTileCells, grid.ny() - j0);
  bool changed = false;
  for (int j = j0; j < j0 + nj && !changed; ++j)
    for (int i = i0; i < i0 + ni && !changed; ++i) {
      const float last = sent_m_[static_cast<std::size_t>(grid.index(i, j))];
      changed = std::isnan(last) || std::abs(grid.surface_m(i, j) - last) > kChangeM;
    }
  if (!changed) return false;
  tile_.step = step;
  tile_.sim_time_s = sim_time_s;
  tile_.i0 = i0;
  tile_.j0 = j0;
  tile_.ni = ni;
  tile_.nj = nj;
  tile_.num_cells = ni * nj;
  tile_.surface_m.clear();
  for (int j = j0; j < j0 + nj; ++j)
    for (int i = i0; i < i0 + ni; ++i) {
      const auto h = static_cast<float>(grid.surface_m(i, j));
      tile_.surface_m.push_back(h);
      sent_m_[static_cast<std::size_t>(grid.index(i, j))] = h;
    }
  return true;
}

}  // namespace skidsim::session
