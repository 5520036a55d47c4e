// The DEM reference's wheel runs (dem/wheel/results, scripts/dem_reference.sh)
// and skidsim's wheel in the same case, compared in dimensionless form: z / D,
// DP / W and T / (W r) against slip. The DEM wheel is lab-sized (0.3 m
// across, 8 mm grains); skidsim runs it at the same size in `dem_sand`, whose
// Bekker, unloading and Janosi parameters come from the DEM's plate and
// shear-box tests (dem/README.md), never from these runs, with the cells as
// many per wheel diameter as the loader's tyre has in a session.
// Used by `skidsim bench report` (perf_wheels_dem.cpp) and its tests.
#pragma once

#include <filesystem>
#include <vector>

#include "experiments/loading_experiments.h"
#include "terrain/flow_law.h"
#include "terrain/soil_mechanics.h"

namespace skidsim::report::perf {

// One LIGGGHTS wheel run: a row of dem/wheel/results/summary.csv, means over
// the steady part of the travel.
struct DemWheel {
  bool towed = false;  // free to spin; otherwise the slip was held
  double slip = 0.0;   // (r omega - v) / max(r omega, v), from the wheel's motion
  double load_N = 0.0, drawbar_pull_N = 0.0, torque_Nm = 0.0, sinkage_m = 0.0;
  double drawbar_pull_sd_N = 0.0, torque_sd_Nm = 0.0, sinkage_sd_m = 0.0;  // scatter of 7.5 ms means
  double radius_m = 0.0, width_m = 0.0, bed_depth_m = 0.0, speed_m_s = 0.0, travel_m = 0.0;
  double rim_friction_angle_deg = 0.0;  // the rim's material on the soil (its own sliding-plate test)
};

// The runs in `dir`, in increasing slip; throws std::runtime_error naming
// the file and column when one is missing or short.
std::vector<DemWheel> read_dem_wheels(const std::filesystem::path& dir);

// The loader's tyre (0.82 m across) has 16.4 cells per diameter at the
// sessions' 5 cm and 8.2 at 10 cm: the DEM wheel on the grid at the same.
inline constexpr double kSessionCellsPerDiameter5cm = 16.4;
inline constexpr double kSessionCellsPerDiameter10cm = 8.2;

// skidsim's rigid wheel on the grid (experiments/loading_experiments.h
// run_soft_wheel): the DEM's wheel, load, speed, travel and rim friction, on
// a bed as deep, driven at the DEM's slip or towed, with cells
// D / cells_per_diameter.
struct WheelLike {
  terrain::SoftWheelRun run;
  double cost = 0.0;  // wall s per simulated s
};
WheelLike wheel_like(const DemWheel& dem, const terrain::SoilMechanics& soil, const terrain::SoilFlowParameters& flow,
                     double cells_per_diameter);

// The Wong-Reece closed form (experiments/wong_reece_closed_form.h) for the
// DEM's wheel, load and rim friction in `soil`, at the DEM's slip (towed:
// its own towed slip).
struct WheelReference {
  double slip = 0.0, sinkage_m = 0.0, drawbar_pull_N = 0.0, torque_Nm = 0.0;
};
WheelReference closed_form_like(const DemWheel& dem, const terrain::SoilMechanics& soil);

}  // namespace skidsim::report::perf
