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

// The most cells a site may have along a side, for the command line's
// --site-m / --cell-m and for height maps read from files alike: a square
// of 16384^2 cells takes 5.6 GB of automaton state, past any machine the
// simulator runs on (jobs/pour_job.cpp).
constexpr int kMaxSiteCellsPerSide = 16384;

// Cell sizes a height map may give: 1 mm (finer than any grid the flow
// law's sub-steps allow at a useful step) to 10 m (coarser than any site).
constexpr double kMinHeightmapCell_m = 1.0e-3;
constexpr double kMaxHeightmapCell_m = 10.0;

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
// file and field: a file that is missing, not a regular file or too large
// (io/input_file.h); JSON that does not parse (with the byte and line); a
// field that is unknown, missing, of the wrong type, not finite or out of
// its physical range (nx, ny: 1 to kMaxSiteCellsPerSide; cell_size_m; the
// grid inside +-kMaxCoordinate_m; z_offset_m and the decoded heights within
// the automaton's limits for the quantity: material 0 to 1000 m, base and
// surface within 100 km); a PNG whose header (size, 16-bit greyscale) does
// not match the metadata, refused before any pixel memory is allocated.
Heightmap read_heightmap(const std::string& json_path);

}  // namespace skidsim::io
