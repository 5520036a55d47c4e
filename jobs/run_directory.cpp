#include "jobs/run_directory.h"


namespace skidsim::jobs {

io::Heightmap terrain_snapshot(const terrain::GranularGrid& grid, const std::string& quantity) {
  io::Heightmap map;
  map.nx = grid.nx();
  map.ny = grid.ny();
  map.cell_size_m = grid.cell_size_m();
  map.origin_m = grid.spec().origin_m;
  map.quantity = quantity;
  map.height_m.resize(static_cast<std::size_t>(map.nx) * map.ny);
  for (int j = 0; j < map.ny; ++j)
    for (int i = 0; i < map.nx; ++i)
      map.height_m[static_cast<std::size_t>(grid.index(i, j))] =
          quantity == "surface" ? grid.surface_m(i, j) : grid.material_m(i, j);
  return map;
}

}  // namespace skidsim::jobs
