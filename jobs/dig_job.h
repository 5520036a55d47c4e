// The dig-and-load job: the loader fills its bucket from a sand bank, backs
// out, turns, drives to a truck bed, dumps into it and backs off, driven by
// a built-in scripted operator (closed loops on the bucket's pitch, the
// arm's angle and the machine's heading). It shows material on moving
// bodies end to end (thesis ch. 6): slicing, carrying, spilling, dumping,
// the books.
#pragma once

#include <string>

namespace skidsim::jobs {

struct DigJob {
  std::string soil_id = "dry_sand";
  std::string soil_table_path;  // empty: the shipped assets/soils.xml
  std::string loader_path;      // empty: the shipped loader
  double cells_per_m = 20.0;
  double bank_height_m = 0.5;
  std::string out_dir = "runs/dig";
};

// Runs the job and writes OUT_DIR/{summary.json, phases.csv,
// terrain_surface.{png,json}, truck_material.{png,json}}. Returns the
// process exit code; bad options throw io::InputError naming the option.
int run_dig_job(const DigJob& job);

}  // namespace skidsim::jobs
