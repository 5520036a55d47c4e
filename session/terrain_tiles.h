// The optional terrain channel (SKIDSIM_TERRAIN; README, "File formats"):
// the soil site's surface in square tiles, only those that changed since
// they were last sent (every tile the first time). Read between control
// ticks, never in the 2 ms step.
#pragma once

#include <vector>

#include "skidsim_lcm/terrain_tile_t.hpp"
#include "terrain/granular_grid.h"

namespace skidsim::session {

class TerrainTiles {
 public:
  static constexpr int kTileCells = 32;
  // A surface moving less than this is not a change worth sending.
  static constexpr double kChangeM = 0.001;

  explicit TerrainTiles(const terrain::GranularGrid& grid);
  // Calls publish(const skidsim_lcm::terrain_tile_t&) for each tile that
  // changed by more than kChangeM since it was last sent, and remembers what
  // it sent. Returns how many it sent.
  template <class Publish>
  int send_changed(const terrain::GranularGrid& grid, long step, double sim_time_s, Publish&& publish) {
    int sent = 0;
    for (int tj = 0; tj < tiles_y_; ++tj)
      for (int ti = 0; ti < tiles_x_; ++ti)
        if (fill_if_changed(grid, ti, tj, step, sim_time_s)) {
          publish(tile_);
          ++sent;
        }
    return sent;
  }

 private:
  bool fill_if_changed(const terrain::GranularGrid& grid, int ti, int tj, long step, double sim_time_s);

  int tiles_x_ = 0, tiles_y_ = 0;
  std::vector<float> sent_m_;  // per cell: the surface last sent (NaN: never)
  skidsim_lcm::terrain_tile_t tile_{};
};

}  // namespace skidsim::session
