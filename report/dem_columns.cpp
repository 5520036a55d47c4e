#include "report/dem_columns.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "common/physical_constants.h"
#include "report/perf_report_parts.h"

namespace skidsim::report::perf {

namespace fs = std::filesystem;

namespace {

// A quantity of a calibration's CSV; throws naming the file and the quantity when it is missing.
double quantity_in(const std::map<std::string, double>& m, const fs::path& file, const std::string& name) {
  const auto it = m.find(name);
  if (it == m.end()) throw std::runtime_error(file.string() + ": no quantity " + name);
  return it->second;
}

// The calibration's grain size and its floor as a flowing layer feels it
// (its stop angle and the rise of its friction with the inertial number).
struct GrainsAndFloor {
  double grain_m = 0.0, floor_deg = 0.0, floor_rate_i0 = 0.0;
};
GrainsAndFloor grains_and_floor(const std::map<std::string, double>& m, const fs::path& file) {
  return {quantity_in(m, file, "particle_diameter_m"), quantity_in(m, file, "floor_flowing_friction_angle_deg"),
          quantity_in(m, file, "floor_rate_friction_i0")};
}

}  // namespace

std::vector<DemColumn> read_dem_columns(const fs::path& dem_dir, const std::string& results) {
  const fs::path dir = dem_dir / "collapse" / results;
  const fs::path material = columns_material(dem_dir, results);
  const std::map<std::string, double> m = read_csv_quantities(material);
  auto quantity = [&](const std::string& name) { return quantity_in(m, material, name); };
  const GrainsAndFloor calibrated = grains_and_floor(m, material);
  // The walls only where a slot was run (a side study's calibration has none).
  const bool walls = m.count("slot_wall_flowing_friction_angle_deg") > 0;
  const double wall_deg = walls ? quantity("slot_wall_flowing_friction_angle_deg") : 0.0;
  const fs::path summary = dir / "summary.csv";
  const CsvNumbers csv = read_csv_numbers(summary);
  std::vector<DemColumn> out;
  for (const auto& row : csv.rows) {
    DemColumn c;
    c.floor_friction_deg = calibrated.floor_deg;
    c.floor_rate_friction_i0 = calibrated.floor_rate_i0;
    c.slot_wall_friction_deg = wall_deg;
    c.grain_diameter_over_r0 = calibrated.grain_m / row[csv.column("r0_m", summary)];
    c.slot = row[csv.column("slot", summary)] != 0.0;
    if (c.slot && !walls) quantity("slot_wall_flowing_friction_angle_deg");  // throws, naming the file
    c.aspect = row[csv.column("aspect_ratio", summary)];
    c.released_aspect = row[csv.column("released_aspect", summary)];
    if (!(c.released_aspect > 0.0))
      throw std::runtime_error(summary.string() + ": row " + std::to_string(out.size() + 2) + ": released_aspect " +
                               fmt("%g", c.released_aspect) + " is not > 0");
    c.drop_over_r0 = row[csv.column("drop_m", summary)] / row[csv.column("r0_m", summary)];
    c.runout = row[csv.column("runout_r99_rel", summary)];
    c.edge_runout = row[csv.column("runout_edge_rel", summary)];
    c.height = row[csv.column("final_height_rel", summary)];
    c.t_stop_scaled = row[csv.column("t_stop_over_sqrt_H0_g", summary)];
    const double r0 = row[csv.column("r0_m", summary)], h = c.released_aspect * r0;
    const std::string geometry = c.slot ? "slot" : c.drop_over_r0 > 0.0 ? "drop" : "tube";
    const fs::path front = dir / ("front_" + geometry + "_a" + fmt("%g", c.aspect) + ".csv");
    const CsvNumbers f = read_csv_numbers(front);
    const std::size_t t = f.column("t_s", front), r = f.column("front_r99_m", front);
    for (const auto& fr : f.rows)
      c.front.emplace_back(fr[t] / std::sqrt(h / kGravity_m_s2), (fr[r] - f.rows.front()[r]) / r0);
    // The deposit's bins (centres r_m, equal widths) hold their thickness
    // over a ring 2 pi r w wide (a strip in the slot).
    const fs::path deposit = dir / ("deposit_" + geometry + "_a" + fmt("%g", c.aspect) + ".csv");
    const CsvNumbers p = read_csv_numbers(deposit);
    const std::size_t pr = p.column("r_m", deposit), ph = p.column("thickness_m", deposit);
    if (p.rows.size() < 2) throw std::runtime_error(deposit.string() + ": fewer than two bins");
    const double w = p.rows[1][pr] - p.rows[0][pr];
    // The bins from the axis out, each w wide: r_m their centres.
    for (std::size_t k = 0; k < p.rows.size(); ++k)
      if (!(w > 0.0 && std::abs(p.rows[k][pr] - (k + 0.5) * w) <= 1e-3 * w))
        throw std::runtime_error(deposit.string() + ": row " + std::to_string(k + 2) + ": r_m " + fmt("%g", p.rows[k][pr]) +
                                 " is not the centre of bin " + std::to_string(k) + " of width " + fmt("%g", w) + " from the axis");
    double total = 0.0;
    for (const auto& bin : p.rows) {
      c.deposit.outer_over_r0.push_back((bin[pr] + 0.5 * w) / r0);
      c.deposit.share.push_back(bin[ph] * (c.slot ? w : 2.0 * kPi * bin[pr] * w));
      total += c.deposit.share.back();
    }
    if (!(total > 0.0)) throw std::runtime_error(deposit.string() + ": thickness_m holds no mass");
    for (double& share : c.deposit.share) share /= total;
    out.push_back(c);
  }
  return out;
}

fs::path columns_material(const fs::path& dem_dir, const std::string& results) {
  const fs::path own = dem_dir / "collapse" / results / "material.csv";
  return fs::exists(own) ? own : dem_dir / "calibration" / "material.csv";
}

terrain::SoilFlowParameters calibrated_flow(const fs::path& material_csv, terrain::SoilFlowParameters base) {
  const std::map<std::string, double> m = read_csv_quantities(material_csv);
  auto quantity = [&](const std::string& name) { return quantity_in(m, material_csv, name); };
  const double stop_below_repose_deg = base.repose_angle_deg - base.stop_angle_deg;
  base.repose_angle_deg = quantity("repose_angle_deg");
  base.stop_angle_deg = base.repose_angle_deg - stop_below_repose_deg;
  base.flowing_friction_angle_deg = quantity("flowing_friction_angle_deg");
  base.thin_layer_friction_angle_deg = quantity("thin_layer_friction_angle_deg");
  base.thin_layer_decay_grains = quantity("thin_layer_decay_grains");
  base.grain_diameter_m = quantity("particle_diameter_m");
  base.bed_start_angle_deg = quantity("bed_start_angle_deg");
  // The friction's rise with the inertial number where the material gives it.
  const bool rate = m.count("rate_friction_angle_deg") > 0;
  base.rate_friction_angle_deg = rate ? quantity("rate_friction_angle_deg") : 0.0;
  base.rate_friction_i0 = rate ? quantity("rate_friction_i0") : 0.0;
  return base;
}

std::string column_name(const DemColumn& c) {
  // A column that stood short of the deck's H0 when released (by more than
  // a grain) is named with its released aspect ratio too.
  const std::string released =
      std::abs(c.released_aspect - c.aspect) > c.grain_diameter_over_r0 ? " (released at " + fmt("%.2f", c.released_aspect) + ")" : "";
  if (c.drop_over_r0 > 0.0) return "dropped " + fmt("%g", c.drop_over_r0) + " r0, a = " + fmt("%g", c.aspect) + released;
  return std::string(c.slot ? "slot" : "tube") + ", a = " + fmt("%g", c.aspect) + released;
}

terrain::CollapseCase dem_column_case(const DemColumn& dem, double cell_m, bool momentum, bool raining) {
  terrain::CollapseCase c;
  c.slot = dem.slot;
  c.aspect = dem.released_aspect;
  c.cell_m = cell_m;
  c.momentum = momentum;
  c.momentum_params.raining = raining;
  c.momentum_params.floor_friction_deg = dem.floor_friction_deg;
  c.momentum_params.floor_rate_friction_i0 = dem.floor_rate_friction_i0;
  c.momentum_params.grain_diameter_m = dem.grain_diameter_over_r0 * c.r0_m;
  c.drop_over_r0 = dem.drop_over_r0;
  c.slot_wall_friction_deg = dem.slot_wall_friction_deg;
  return c;
}

terrain::CollapseCase wide_tube_case(const DemColumn& dem, double cell_m) {
  terrain::CollapseCase c = dem_column_case(dem, cell_m, true, true);
  c.max_time_s = 60.0 * std::sqrt(dem.released_aspect * c.r0_m / kGravity_m_s2);
  return c;
}

double compared_runout(const DemColumn& dem) { return dem.drop_over_r0 > 0.0 ? dem.edge_runout : dem.runout; }
double compared_runout(const DemColumn& dem, const terrain::CollapseRun& run) {
  return dem.drop_over_r0 > 0.0 ? run.edge_runout_over_r0 : run.runout_over_r0;
}

double column_error(const DemColumn& dem, const terrain::CollapseRun& run) {
  return std::max(std::abs(compared_runout(dem, run) / compared_runout(dem) - 1.0),
                  std::abs(run.final_height_over_r0 / dem.height - 1.0));
}

double mass_within(const MassProfile& p, double r_over_r0) {
  double inside = 0.0, inner = 0.0;
  for (std::size_t k = 0; k < p.share.size(); ++k) {
    const double outer = p.outer_over_r0[k];
    if (r_over_r0 >= outer) inside += p.share[k];
    else if (r_over_r0 > inner) inside += p.share[k] * (r_over_r0 - inner) / (outer - inner);
    inner = outer;
  }
  return inside;
}

double mass_gap(const MassProfile& a, const MassProfile& b, double* at_over_r0) {
  // Both shares are linear between the bins' edges: the largest difference
  // lies on one of them.
  double gap = 0.0, at = 0.0;
  for (const MassProfile* p : {&a, &b})
    for (double r : p->outer_over_r0) {
      const double g = std::abs(mass_within(a, r) - mass_within(b, r));
      if (g > gap) gap = g, at = r;
    }
  if (at_over_r0) *at_over_r0 = at;
  return gap;
}

MassProfile deposit_profile(const terrain::CollapseRun& run) {
  MassProfile p;
  double total = 0.0;
  for (double v : run.deposit_volume_m3) total += v;
  for (std::size_t k = 0; k < run.deposit_volume_m3.size(); ++k) {
    p.outer_over_r0.push_back((k + 1) * run.c.cell_m / run.c.r0_m);
    p.share.push_back(total > 0.0 ? run.deposit_volume_m3[k] / total : 0.0);
  }
  return p;
}

double front_arrival(const std::vector<std::pair<double, double>>& front, double fraction) {
  if (front.empty()) return 0.0;
  const double target = fraction * front.back().second;
  for (const auto& [t, x] : front)
    if (x >= target) return t;
  return front.back().first;
}

std::vector<std::pair<double, double>> scaled_front(const terrain::CollapseRun& run) {
  std::vector<std::pair<double, double>> out;
  const double t_scale = std::sqrt(run.c.aspect * run.c.r0_m / kGravity_m_s2);
  for (const auto& fr : run.frames)
    out.emplace_back(fr.t_s / t_scale, (fr.front_r99_m - run.frames.front().front_r99_m) / run.c.r0_m);
  out.emplace_back(run.final_state.t_s / t_scale, run.runout_over_r0);
  return out;
}

std::vector<DemFedHeap> read_dem_fed_heap(const fs::path& dem_dir) {
  const fs::path path = dem_dir / "calibration" / "results" / "fed_heap_summary.csv";
  const CsvNumbers csv = read_csv_numbers(path);
  std::vector<DemFedHeap> out;
  for (const auto& row : csv.rows)
    out.push_back({row[csv.column("Q_m2_s", path)], row[csv.column("tan_mean", path)], row[csv.column("tan_p05", path)],
                   row[csv.column("tan_p95", path)]});
  if (out.empty()) throw std::runtime_error(path.string() + ": no runs");
  return out;
}

terrain::FedHeapCase dem_fed_heap_case(const DemFedHeap& dem, double cell_m, bool momentum) {
  terrain::FedHeapCase c;
  c.q_m2_s = dem.q_m2_s;
  c.lambda = kFedHeapLambda;
  c.cell_m = cell_m;
  c.momentum = momentum;
  return c;
}

double slope_deg(double tan_beta) { return rad_to_deg(std::atan(tan_beta)); }

std::vector<DemStoppingLayer> read_dem_stopping_layers(const fs::path& dem_dir) {
  const fs::path material = dem_dir / "calibration" / "material.csv";
  const std::map<std::string, double> m = read_csv_quantities(material);
  const GrainsAndFloor calibrated = grains_and_floor(m, material);
  const fs::path path = dem_dir / "calibration" / "results" / "stopping_summary.csv";
  const CsvNumbers csv = read_csv_numbers(path);
  std::vector<DemStoppingLayer> out;
  for (const auto& row : csv.rows) {
    DemStoppingLayer d;
    d.base_type = static_cast<int>(row[csv.column("base_type", path)]);
    d.layers = static_cast<int>(row[csv.column("layers", path)]);
    d.theta_deg = row[csv.column("theta_deg", path)];
    d.mean0_m_s = row[csv.column("mean0_m_s", path)];
    d.friction_top = row[csv.column("friction_top", path)];
    d.stop_time_ratio = row[csv.column("stop_time_ratio", path)];
    d.travel_ratio = row[csv.column("travel_ratio", path)];
    d.flowing_m = row[csv.column("fit_flowing_grains", path)] * calibrated.grain_m;
    d.flowing_m_s = row[csv.column("fit_flowing_m_s", path)];
    d.grain_m = calibrated.grain_m;
    d.floor_friction_deg = calibrated.floor_deg;
    d.floor_rate_friction_i0 = calibrated.floor_rate_i0;
    out.push_back(d);
  }
  if (out.empty()) throw std::runtime_error(path.string() + ": no runs");
  return out;
}

terrain::StoppingLayerCase dem_stopping_case(const DemStoppingLayer& dem, double cell_m) {
  terrain::StoppingLayerCase c;
  c.layer_m = dem.layers * dem.grain_m;
  c.speed_m_s = dem.mean0_m_s;
  c.cell_m = cell_m;
  c.on_floor = dem.base_type == 3;
  c.floor_friction_deg = dem.floor_friction_deg;
  return c;
}

}  // namespace skidsim::report::perf
