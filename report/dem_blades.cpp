#include "report/dem_blades.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "common/physical_constants.h"
#include "jobs/push_job.h"
#include "report/perf_report_parts.h"

namespace skidsim::report::perf {

namespace fs = std::filesystem;

// dem/blade/results/summary.csv, and the heap after 1.5 d of travel from
// heap_summary.csv beside it (dem/tools/heap.py).
std::vector<DemBlade> read_dem_blades(const fs::path& dir) {
  const fs::path summary = dir / "summary.csv", heaps = dir / "heap_summary.csv";
  const CsvNumbers t = read_csv_numbers(summary);
  const auto c = [&](const char* name) { return t.column(name, summary); };
  const std::size_t rake = c("rake_deg"), depth = c("depth_m"), width = c("width_m"), density = c("bulk_density_kg_m3"),
                    peak = c("N_peak"), mean = c("N_mean"), from = c("mean_window_from_m"), travel = c("travel_m"),
                    fx = c("mean_force_x_N"), fz = c("mean_force_z_N");
  const CsvNumbers h = read_csv_numbers(heaps);
  const std::size_t h_rake = h.column("rake_deg", heaps), h_depth = h.column("depth_m", heaps),
                    h_front = h.column("front_d2", heaps), h_face = h.column("on_face_d2", heaps);
  std::vector<DemBlade> out;
  for (const std::vector<double>& v : t.rows) {
    DemBlade b{v[rake], v[depth], v[width], v[density], v[peak], v[mean], v[from], v[travel], v[fz] / v[fx], -1.0, 0.0};
    for (const std::vector<double>& r : h.rows)
      if (std::abs(r[h_rake] - b.rake_deg) < 1e-9 && std::abs(r[h_depth] - b.depth_m) < 1e-6)
        b.heap_front_d2 = r[h_front], b.heap_on_face_d2 = r[h_face];
    out.push_back(b);
  }
  return out;
}

// skidsim's push of a 1 m blade at the DEM case's d/w and rake, over the same
// travel over d; N's mean over the DEM's window (from the same travel over d).
PushResult push_like(const DemBlade& dem, double cells_per_m, const fs::path& work) {
  const double scale = 1.0 / dem.width_m;  // a 1 m blade
  jobs::PushJob p;
  p.soil_id = "dem_sand";
  p.cutting_model = "earthmoving";
  p.cells_per_m = cells_per_m;
  p.width_m = 1.0;
  p.depth_m = dem.depth_m * scale;
  p.layer_m = 2.0 * p.depth_m + 0.4;
  p.rake_deg = dem.rake_deg;
  p.distance_m = dem.travel_m * scale;
  p.out_dir = work.string();
  if (jobs::run_push_job(p) != 0) throw std::runtime_error("performance report: the DEM-scale push failed");
  const nlohmann::json s = read_summary(work);
  const double gamma_d2_w =
      s["soil"]["bulk_density_kg_m3"].get<double>() * kGravity_m_s2 * p.depth_m * p.depth_m * p.width_m;
  const fs::path path = work / "resistance.csv";
  const CsvNumbers t = read_csv_numbers(path);
  const std::size_t at = t.column("distance_m", path), draft = t.column("resistance_N", path),
                    weight = t.column("wedge_weight_N", path), down = t.column("face_vertical_down_N", path);
  PushResult r;
  double sum = 0.0, sum_down = 0.0, heap_weight = -1.0;
  int n = 0;
  for (const std::vector<double>& v : t.rows) {
    if (heap_weight < 0.0 && v[at] >= 1.5 * p.depth_m - 1e-9) heap_weight = v[weight];
    r.n_along.emplace_back(v[at] / p.depth_m, v[draft] / gamma_d2_w);
    if (v[at] >= dem.mean_from_m * scale - 1e-9) sum += v[draft], sum_down += v[down], ++n;
  }
  const double first_weight = t.rows.empty() ? 0.0 : t.rows.front()[weight];
  r.heap_d2 = (heap_weight - first_weight) / gamma_d2_w;
  r.up_over_draft = sum > 0.0 ? -sum_down / sum : 0.0;
  r.up_over_draft_equation = -s["reference"]["earthmoving_vertical_down_N"].get<double>() /
                             s["reference"]["earthmoving_N"].get<double>();
  r.n_equation = s["reference"]["earthmoving_N_over_gamma_d2_w"].get<double>();
  r.n_mean = n > 0 ? sum / n / gamma_d2_w : 0.0;
  r.cost = s["performance"]["us_per_step"].get<double>() * 1e-6 / 0.002;
  return r;
}

// The DEM's draft along the travel, N against travel over d
// (blade_a{rake}_d{mm}mm.csv: travel_m, force_x_N, force_z_N).
std::vector<std::pair<double, double>> dem_n_along(const fs::path& dir, const DemBlade& dem) {
  const fs::path path = dir / ("blade_a" + fmt("%g", dem.rake_deg) + "_d" + fmt("%.0f", dem.depth_m * 1000.0) + "mm.csv");
  const CsvNumbers t = read_csv_numbers(path);
  const std::size_t travel = t.column("travel_m", path), fx = t.column("force_x_N", path);
  const double gamma_d2_w = dem.density_kg_m3 * kGravity_m_s2 * dem.depth_m * dem.depth_m * dem.width_m;
  std::vector<std::pair<double, double>> out;
  for (const std::vector<double>& v : t.rows) out.emplace_back(v[travel] / dem.depth_m, v[fx] / gamma_d2_w);
  return out;
}

}  // namespace skidsim::report::perf
