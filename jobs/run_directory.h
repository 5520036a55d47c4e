// Run directories (io/run_directory.h) and what the jobs put in them.
#pragma once

#include <filesystem>
#include <string>

#include "io/heightmap.h"
#include "io/run_directory.h"
#include "terrain/granular_grid.h"

namespace skidsim::jobs {

using io::StagedRunDirectory;

// The grid's surface ("surface") or loose material depth ("material") as a
// height map.
io::Heightmap terrain_snapshot(const terrain::GranularGrid& grid, const std::string& quantity);

}  // namespace skidsim::jobs
