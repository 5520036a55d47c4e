// Height maps on disk: a 16-bit greyscale PNG plus a JSON metadata file that
// says where the grid lies and how pixel values map to metres.
//
//   metres = z_offset_m + vertical_scale_m * pixel
//   pixel (col, row): grid cell i = col, j = ny - 1 - row (north/+y up)
//   cell (i, j) centre = origin_m + cell_size_m * (i, j)
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace skidsim::io {

struct Heightmap {
  int nx = 0;
  int ny = 0;
  double cell_size_m = 0.0;
  Eigen::Vector2d origin_m = Eigen::Vector2d::Zero();
  std::string quantity = "surface";  // surface, material or base
  std::vector<double> height_m;      // row-major, index j * nx + i

  double at(int i, int j) const { return height_m[static_cast<std::size_t>(j) * nx + i]; }
};

struct HeightmapFileInfo {
  double z_offset_m = 0.0;
  double vertical_scale_m = 0.0;  // metres per pixel step; error <= half of it
};

// Writes PATH_STEM.png and PATH_STEM.json (each atomically). The vertical
// scale is the height range over 65535, or `min_vertical_scale_m` if that is
// larger (a flat map). Throws on non-finite heights or I/O failure.
HeightmapFileInfo write_heightmap(const std::string& path_stem, const Heightmap& map,
                                  double min_vertical_scale_m = 1e-6);

// Reads PATH_STEM.json and the PNG it names. Throws InputError naming the
// file and field on a missing file, a PNG that is not 16-bit greyscale, or
// metadata that does not match the image.
Heightmap read_heightmap(const std::string& json_path);

}  // namespace skidsim::io
