#include "report/dem_wheels.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "experiments/wong_reece_closed_form.h"
#include "report/perf_report_parts.h"
#include "terrain/granular_grid.h"

namespace skidsim::report::perf {

namespace fs = std::filesystem;

std::vector<DemWheel> read_dem_wheels(const fs::path& dir) {
  const fs::path path = dir / "summary.csv";
  const CsvNumbers t = read_csv_numbers(path);
  const auto c = [&](const char* name) { return t.column(name, path); };
  const std::size_t towed = c("towed"), slip = c("slip"), load = c("load_N"), dp = c("drawbar_pull_N"),
                    dp_sd = c("drawbar_pull_sd_N"), torque = c("torque_Nm"), torque_sd = c("torque_sd_Nm"),
                    sinkage = c("sinkage_m"), sinkage_sd = c("sinkage_sd_m"), radius = c("radius_m"),
                    width = c("width_m"), depth = c("bed_depth_m"), speed = c("speed_m_s"), travel = c("travel_m"),
                    rim = c("rim_friction_angle_deg");
  std::vector<DemWheel> out;
  for (const std::vector<double>& v : t.rows) {
    DemWheel w;
    w.towed = v[towed] > 0.5;
    w.slip = v[slip];
    w.load_N = v[load], w.drawbar_pull_N = v[dp], w.torque_Nm = v[torque], w.sinkage_m = v[sinkage];
    w.drawbar_pull_sd_N = v[dp_sd], w.torque_sd_Nm = v[torque_sd], w.sinkage_sd_m = v[sinkage_sd];
    w.radius_m = v[radius], w.width_m = v[width], w.bed_depth_m = v[depth], w.speed_m_s = v[speed];
    w.travel_m = v[travel];
    w.rim_friction_angle_deg = v[rim];
    out.push_back(w);
  }
  std::sort(out.begin(), out.end(), [](const DemWheel& a, const DemWheel& b) { return a.slip < b.slip; });
  return out;
}

WheelLike wheel_like(const DemWheel& dem, const terrain::SoilMechanics& soil, const terrain::SoilFlowParameters& flow,
                     double cells_per_diameter) {
  constexpr double kStepS = 0.002;
  // run_soft_wheel starts at (0.61, 0.79) m: room for the travel, the
  // contact and the rut's sides beyond.
  const double cell_m = 2.0 * dem.radius_m / cells_per_diameter;
  terrain::GridSpec spec;
  spec.cell_size_m = cell_m;
  spec.nx = static_cast<int>(std::ceil((0.62 + dem.travel_m + 2.0 * dem.radius_m + 0.2) / cell_m));
  spec.ny = static_cast<int>(std::ceil(1.58 / cell_m));
  terrain::GranularGrid grid(spec, flow, kStepS);
  for (int j = 0; j < spec.ny; ++j)
    for (int i = 0; i < spec.nx; ++i) grid.set_material_m(i, j, dem.bed_depth_m);
  const double slip = dem.towed ? std::numeric_limits<double>::quiet_NaN() : dem.slip;
  const auto start = std::chrono::steady_clock::now();
  WheelLike out;
  out.run = terrain::run_soft_wheel(grid, soil, dem.load_N / kGravity_m_s2, dem.radius_m, dem.width_m, slip,
                                    dem.speed_m_s, dem.travel_m, dem.bed_depth_m, kStepS,
                                    deg_to_rad(dem.rim_friction_angle_deg));
  out.cost = seconds_since(start) / out.run.simulated_s;
  return out;
}

WheelReference closed_form_like(const DemWheel& dem, const terrain::SoilMechanics& soil) {
  closed_form::WongReeceSoil ref = closed_form::reference_soil_of(soil);
  ref.rim_delta_rad = deg_to_rad(dem.rim_friction_angle_deg);
  const double r = dem.radius_m, b = dem.width_m;
  WheelReference out;
  out.slip = dem.towed ? closed_form::wong_reece_reference_towed_slip(ref, r, b, dem.load_N) : dem.slip;
  out.sinkage_m = closed_form::wong_reece_reference_sinkage(ref, r, b, dem.load_N, out.slip);
  const closed_form::WongReeceResult f = closed_form::wong_reece_reference(ref, r, b, out.sinkage_m, out.slip);
  out.drawbar_pull_N = f.DP;
  out.torque_Nm = f.T;
  return out;
}

}  // namespace skidsim::report::perf
