// The terrain-only main job (until the exercise runner exists): pour sand from
// a hopper onto a site, let it settle, and write a run directory.
#pragma once

#include <string>

#include "terrain/granular_grid.h"

namespace skidsim::jobs {

struct PourJob {
  std::string soil_id = "dry_sand";
  std::string soil_table_path;  // empty: the shipped assets/soils.xml
  double site_size_m = 8.0;     // square site, the thesis's 8 m x 8 m yard
  double cell_size_m = 0.05;
  double layer_depth_m = 0.0;   // initial flat layer of the same soil
  double hopper_radius_m = 0.1;
  double pour_rate_kg_per_s = 100.0;
  double pour_duration_s = 15.0;
  double max_settle_s = 30.0;   // stop earlier once the terrain is at rest
  double step_dt_s = 0.002;
  bool open_edges = false;
  // Optional height maps (skidsim-heightmap JSON) for the initial terrain:
  // material depth and hard base. Either sets the grid (size, cell, origin)
  // in place of site_size_m and cell_size_m; given both, they must agree.
  std::string material_map_path;
  std::string base_map_path;
  std::string out_dir = "runs/pour";
};

// Runs the job and writes OUT_DIR/{summary.json, terrain_surface.{png,json},
// terrain_material.{png,json}}. Returns the process exit code. Errors in the
// input are reported on stderr naming the file and field.
int run_pour_job(const PourJob& job);

}  // namespace skidsim::jobs
