// Run directories: written into a staging folder beside the target, which
// replaces the target only once complete, so a failed run leaves the
// previous results (or nothing), never a mixture.
#pragma once

#include <filesystem>
#include <string>

#include "io/heightmap.h"
#include "terrain/granular_grid.h"

namespace skidsim::apps {

class StagedRunDirectory {
 public:
  explicit StagedRunDirectory(const std::string& out_dir);
  ~StagedRunDirectory();  // removes the staging folder unless committed
  StagedRunDirectory(const StagedRunDirectory&) = delete;
  StagedRunDirectory& operator=(const StagedRunDirectory&) = delete;

  // Where the files go until commit().
  const std::filesystem::path& staging() const { return staging_; }
  // Replaces the target directory with the staging folder.
  void commit();

 private:
  std::filesystem::path out_dir_, staging_;
  bool committed_ = false;
};

// The grid's surface ("surface") or loose material depth ("material") as a
// height map.
io::Heightmap terrain_snapshot(const terrain::GranularGrid& grid, const std::string& quantity);

}  // namespace skidsim::apps
