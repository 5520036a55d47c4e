#include "apps/run_directory.h"

#include <unistd.h>

#include "io/atomic_file.h"

namespace skidsim::apps {

namespace fs = std::filesystem;

namespace {

// "runs/x/" and "runs/x" name the same directory; the staging folder must
// sit beside it, not inside it.
fs::path run_directory_path(const std::string& out_dir) {
  fs::path p = fs::path(out_dir).lexically_normal();
  if (!p.empty() && !p.has_filename()) p = p.parent_path();
  const std::string name = p.filename().string();
  if (name.empty() || name == "." || name == "..")
    throw io::InputError("--out \"" + out_dir + "\": expected a directory name (not empty, '.' or '..')");
  return p;
}

}  // namespace

StagedRunDirectory::StagedRunDirectory(const std::string& out_dir)
    : out_dir_(run_directory_path(out_dir)),
      staging_(out_dir_.string() + ".partial-" + std::to_string(::getpid())) {
  fs::remove_all(staging_);
  fs::create_directories(staging_);
}

StagedRunDirectory::~StagedRunDirectory() {
  std::error_code ignored;
  if (!committed_) fs::remove_all(staging_, ignored);
}

void StagedRunDirectory::commit() {
  if (fs::exists(out_dir_)) {
    const fs::path replaced = out_dir_.string() + ".replaced-" + std::to_string(::getpid());
    fs::rename(out_dir_, replaced);
    try {
      fs::rename(staging_, out_dir_);
    } catch (...) {
      fs::rename(replaced, out_dir_);  // put the previous results back
      throw;
    }
    fs::remove_all(replaced);
  } else {
    fs::rename(staging_, out_dir_);
  }
  committed_ = true;
}

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

}  // namespace skidsim::apps
