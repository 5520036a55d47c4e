// The DEM reference's collapsing columns (dem/collapse/results,
// scripts/dem_reference.sh) and skidsim's column in the same case, in
// dimensionless form: run-out and final height over r0, the front against
// t / sqrt(H0 / g). The DEM's columns are lab-sized (r0 = 0.1 m, 8 mm
// grains); skidsim's is scaled to r0 = 1 m in `dem_sand`
// (experiments/column_collapse.h). Used by `skidsim bench report`
// (perf_collapse.cpp) and its tests.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "experiments/column_collapse.h"
#include "experiments/fed_heap.h"
#include "experiments/stopping_layer.h"

namespace skidsim::report::perf {

// Where a deposit's mass lies, from the axis (the slot's back wall) out:
// each bin's outer edge over r0 and its share of the mass.
struct MassProfile {
  std::vector<double> outer_over_r0, share;
};
// The share of the mass within r_over_r0 of the axis (the wall), linear
// within a bin.
double mass_within(const MassProfile& p, double r_over_r0);
// How far apart two deposits hold their mass: the largest difference, at
// any distance from the axis, between the shares of their mass within it
// (Kolmogorov-Smirnov's distance between the radial distributions; 0 where
// the mass lies alike), and where (over r0) when `at_over_r0` is given.
double mass_gap(const MassProfile& a, const MassProfile& b, double* at_over_r0 = nullptr);

// One LIGGGHTS column: a row of dem/collapse/results/summary.csv, its
// front_*.csv and its deposit_*.csv. A dropped column's r99 counts the grains its impact scatters
// one by one far out, which no height field holds: compare its edge.
struct DemColumn {
  bool slot = false;
  // The deck's floor and the slot's steel side walls as a flowing layer
  // feels them, from the inclined-layer tests on the same floor and between
  // the same walls (dem/calibration/material.csv, dem/calibration/chute.in),
  // never from the columns: the floor's stop angle (deg) and the walls'
  // friction angle (deg).
  double floor_friction_deg = 0.0, slot_wall_friction_deg = 0.0;
  // The floor's friction's rise with the inertial number (I_0;
  // dem/tools/rate_friction.py).
  double floor_rate_friction_i0 = 0.0;
  // The grains' diameter over r0 (0.008 m / 0.1 m, or / 0.2 m): a thin layer's friction
  // depends on its thickness in grains, which the grid's column keeps.
  double grain_diameter_over_r0 = 0.0;
  // A column let go this far (over r0) above the floor (0: standing on it).
  double drop_over_r0 = 0.0;
  // The deck's aspect ratio (a = H0 / r0, in the files' names) and the
  // column's as released (its top grains' centres over r0,
  // dem/tools/collapse.py): a model collapses the released column. The
  // height H in the time scale sqrt(H / g) is the released one.
  double aspect = 0.0, released_aspect = 0.0;
  double runout = 0.0, edge_runout = 0.0, height = 0.0, t_stop_scaled = 0.0;
  std::vector<std::pair<double, double>> front;  // t / sqrt(H / g), (r99 - r99(0)) / r0
  MassProfile deposit;  // the final deposit's
};

// The columns of the DEM reference in `dem_dir` (the repository's dem/):
// collapse/`results` and calibration/material.csv (kWideTubeResults: the
// same grains in a tube twice as wide). Throws std::runtime_error naming the
// file and column or quantity when one is missing.
std::vector<DemColumn> read_dem_columns(const std::filesystem::path& dem_dir, const std::string& results = "results");
// The tube twice as wide (r0 = 0.2 m, 25 grains per radius;
// scripts/dem_reference.sh, COLLAPSE_WIDE_R0_M).
inline constexpr const char* kWideTubeResults = "results_r0_0.2";
// The friction side study (scripts/dem_reference.sh, stage friction): the
// same tubes in materials whose grains' rolling friction is
// `rolling_friction` for the calibrated 0.3, each calibrated on the pile,
// the inclined layers and the erodible bed alone (collapse/`results` holds
// its material.csv): whether the DEM's run-out follows the material's
// friction as the model's does.
struct FrictionStudyMaterial {
  double rolling_friction;
  const char* results;
};
inline constexpr FrictionStudyMaterial kFrictionStudy[] = {{0.6, "results_mu_r0.6"}, {0.15, "results_mu_r0.15"}};
// The calibration the columns in collapse/`results` were run with: the
// folder's own material.csv (a side study's), else calibration/material.csv.
std::filesystem::path columns_material(const std::filesystem::path& dem_dir, const std::string& results);
// `base` with the flow law's calibrated fields from a DEM calibration
// (material_csv, dem/tools/material_csv.py): the repose angle (the pile),
// the flowing friction and the thin-layer law (the inclined layers), the
// grains' diameter and the bed's start angle (the erodible bed); the stop
// angle, not calibrated, kept `base`'s distance under the repose angle (the
// estimate dem_sand's is, assets/soils.xml). Throws std::runtime_error
// naming the file and the quantity missing.
terrain::SoilFlowParameters calibrated_flow(const std::filesystem::path& material_csv, terrain::SoilFlowParameters base);

std::string column_name(const DemColumn& c);  // "tube, a = 2", "slot, a = 2", "dropped 4 r0, a = 1"
// A tube standing on the floor (not the slot, not a dropped column).
inline bool standing_tube(const DemColumn& c) { return !c.slot && c.drop_over_r0 == 0.0; }
// The DEM column's case on the grid at `cell_m`: the fast flow on when
// `momentum`, at its defaults (bed friction the soil's flowing friction,
// the core at the repose angle, raining) unless `raining` is false, on the
// deck's floor and, in the slot, between its walls (DemColumn).
terrain::CollapseCase dem_column_case(const DemColumn& dem, double cell_m, bool momentum, bool raining);
// A column of the tube twice as wide (kWideTubeResults): the fast flow,
// raining, run for up to 60 sqrt(H0 / g) (a = 0.5's flank trickles on past
// the default 40 at 5 cm).
terrain::CollapseCase wide_tube_case(const DemColumn& dem, double cell_m);

// The run-out compared: r99's, or for a dropped column its edge's (its
// impact scatters single grains far out, DemColumn); and the worst of the
// run-out's and the height's relative errors against the DEM.
double compared_runout(const DemColumn& dem);
double compared_runout(const DemColumn& dem, const terrain::CollapseRun& run);
double column_error(const DemColumn& dem, const terrain::CollapseRun& run);

// Where the grid's final deposit holds its mass (CollapseRun::deposit_volume_m3).
MassProfile deposit_profile(const terrain::CollapseRun& run);

// When the front first reaches `fraction` of its final advance, over
// sqrt(H0 / g); points as DemColumn::front.
double front_arrival(const std::vector<std::pair<double, double>>& front, double fraction);
std::vector<std::pair<double, double>> scaled_front(const terrain::CollapseRun& run);

// The DEM's fed heap (dem/calibration/fed_heap.in, results/fed_heap_summary.csv;
// dem/tools/fed_heap.py): per feed Q (bulk m^2/s per metre of width), the
// slope's tangent over the steady window, mean and 5th and 95th
// percentiles. The model's heap: experiments/fed_heap.h at lambda
// kFedHeapLambda, the collapsing columns' scale (r0 = 0.1 m to 1 m).
struct DemFedHeap {
  double q_m2_s = 0.0, tan_mean = 0.0, tan_p05 = 0.0, tan_p95 = 0.0;
};
std::vector<DemFedHeap> read_dem_fed_heap(const std::filesystem::path& dem_dir);
inline constexpr double kFedHeapLambda = 10.0;
// The DEM run's case on the grid at `cell_m`, the fast flow on when `momentum`.
terrain::FedHeapCase dem_fed_heap_case(const DemFedHeap& dem, double cell_m, bool momentum);
// A slope's tangent in degrees.
double slope_deg(double tan_beta);

// The DEM's layers coming to rest (dem/calibration/stopping.in,
// results/stopping_summary.csv; dem/tools/stopping.py): per run the base (1:
// the layer's own grains, frozen; 3: the columns' floor), its thickness in
// grains, the slope, its first mean speed, the friction that slows its
// flowing grains, and the deposition's dimensionless signature: t_stop a /
// u0 and the mass centre's travel a / u0^2 (a the top's deceleration); with
// the calibration's grain diameter and floor friction, and its rise with the
// inertial number (material.csv). Over the frames that measure the friction:
// the flowing layer's mean depth (above the layers at rest) and its grains'
// mean speed.
struct DemStoppingLayer {
  int base_type = 1, layers = 0;
  double theta_deg = 0.0, mean0_m_s = 0.0, friction_top = 0.0, stop_time_ratio = 0.0, travel_ratio = 0.0;
  double flowing_m = 0.0, flowing_m_s = 0.0;
  double grain_m = 0.0, floor_friction_deg = 0.0, floor_rate_friction_i0 = 0.0;
};
std::vector<DemStoppingLayer> read_dem_stopping_layers(const std::filesystem::path& dem_dir);
// The DEM run's layer on the grid at `cell_m` (the DEM's own size: a uniform
// layer has no length scale but its depth).
terrain::StoppingLayerCase dem_stopping_case(const DemStoppingLayer& dem, double cell_m);

}  // namespace skidsim::report::perf
