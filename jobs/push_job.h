// The blade-push job (thesis 7.3.2, fig. 7.12): a blade at depth H, vertical
// or raked, pushed at constant speed through a flat layer of soil; records
// the soil's resistance (the bound of the soil's cutting model) along the
// push beside the earthmoving equation's value on flat ground.
#pragma once

#include <string>

namespace skidsim::jobs {

struct PushJob {
  std::string soil_id = "dry_sand";
  std::string soil_table_path;  // empty: the shipped assets/soils.xml
  double cells_per_m = 20.0;
  double layer_m = 0.4;         // flat layer of soil on a flat base
  double depth_m = 0.2;         // H: the blade's edge below the surface
  double width_m = 1.0;         // B
  double rake_deg = 90.0;       // the face's angle from the horizontal (90: vertical)
  std::string cutting_model;    // empty: the soil table's; else "earthmoving" or "thesis_wedge"
  double speed_m_s = 1.0;
  double distance_m = 4.0;
  double step_dt_s = 0.002;
  std::string out_dir = "runs/push";
};

// Runs the job and writes OUT_DIR/{summary.json, resistance.csv,
// terrain_surface.{png,json}}. Returns the process exit code; bad options
// throw io::InputError naming the option.
int run_push_job(const PushJob& job);

}  // namespace skidsim::jobs
