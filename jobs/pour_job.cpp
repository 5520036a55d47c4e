#include "jobs/pour_job.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <vector>

#include "jobs/interrupt.h"
#include "jobs/progress.h"
#include "jobs/run_directory.h"
#include "io/atomic_file.h"
#include "io/heightmap.h"
#include "io/soil_table.h"
#include "terrain/pile_metrics.h"

namespace skidsim::jobs {
using nlohmann::json;

// The site before the pour: its grid from the options or from the height
// maps given (which set the grid), the maps' heights, the flat layer.
std::unique_ptr<terrain::GranularGrid> initial_grid(const PourJob& job, const terrain::SoilFlowParameters& soil) {
  // Between 3 and kMaxSiteCellsPerSide cells across (16384^2 cells take
  // 5.6 GB of state); height maps are held to the same cap (io/heightmap.h).
  constexpr double kMaxCells = io::kMaxSiteCellsPerSide;
  const double cells_across = job.site_size_m / job.cell_size_m;
  if (!(cells_across >= 2.5 && cells_across <= kMaxCells) && job.material_map_path.empty() && job.base_map_path.empty()) {
    throw io::InputError("--site-m " + std::to_string(job.site_size_m) + " and --cell-m " +
                         std::to_string(job.cell_size_m) + " give " + std::to_string(cells_across) +
                         " cells across the site (expected 3 to " + std::to_string(io::kMaxSiteCellsPerSide) + ")");
  }
  terrain::GridSpec spec;
  spec.nx = spec.ny = static_cast<int>(std::lround(std::clamp(cells_across, 1.0, kMaxCells)));
  spec.cell_size_m = job.cell_size_m;
  spec.origin_m = {0.5 * job.cell_size_m, 0.5 * job.cell_size_m};
  spec.edges.fill(job.open_edges ? terrain::EdgeKind::kOpen : terrain::EdgeKind::kClosed);

  // Initial terrain from height maps, when given.
  std::vector<std::pair<std::string, io::Heightmap>> maps;
  for (const auto& [path, quantity] : {std::pair{job.material_map_path, "material"}, std::pair{job.base_map_path, "base"}}) {
    if (path.empty()) continue;
    io::Heightmap map = io::read_heightmap(path);
    if (map.quantity != quantity)
      throw io::InputError(path + ": field 'quantity' is \"" + map.quantity + "\" (expected \"" + quantity + "\")");
    if (maps.empty()) {
      spec.nx = map.nx;
      spec.ny = map.ny;
      spec.cell_size_m = map.cell_size_m;
      spec.origin_m = map.origin_m;
    } else if (map.nx != spec.nx || map.ny != spec.ny || map.cell_size_m != spec.cell_size_m ||
               map.origin_m != spec.origin_m) {
      throw io::InputError(path + ": fields 'nx', 'ny', 'cell_size_m', 'origin_m' differ from " + maps.front().first);
    }
    maps.emplace_back(path, std::move(map));
  }
  auto grid_ptr = std::make_unique<terrain::GranularGrid>(spec, soil, job.step_dt_s);
  terrain::GranularGrid& grid = *grid_ptr;
  for (const auto& [path, map] : maps) {
    try {  // out-of-range heights are refused by the grid; name the file
      for (int j = 0; j < spec.ny; ++j)
        for (int i = 0; i < spec.nx; ++i) {
          if (map.quantity == "base") {
            grid.set_base_m(i, j, map.at(i, j));
          } else {
            grid.set_material_m(i, j, map.at(i, j));
          }
        }
    } catch (const std::invalid_argument& e) {
      throw io::InputError(path + ": " + e.what());
    }
  }
  try {
    if (job.layer_depth_m > 0.0)
      for (int j = 0; j < spec.ny; ++j)
        for (int i = 0; i < spec.nx; ++i) grid.set_material_m(i, j, grid.material_m(i, j) + job.layer_depth_m);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(std::string("--layer-m: ") + e.what());
  }
  return grid_ptr;
}

int run_pour_job(const PourJob& job) {
  const jobs::InterruptScope interrupt_scope;  // a signal stops the job; the previous result stays
  namespace fs = std::filesystem;
  const std::string table_path = job.soil_table_path.empty() ? io::default_soil_table_path() : job.soil_table_path;
  const io::SoilTable table = io::load_soil_table(table_path);
  const auto it = table.find(job.soil_id);
  if (it == table.end()) {
    std::cerr << "skidsim: soil '" << job.soil_id << "' is not in " << table_path << " (known:";
    for (const auto& [id, rec] : table) std::cerr << " " << id;
    std::cerr << ")\n";
    return 2;
  }
  const terrain::SoilFlowParameters& soil = it->second.flow;

  const std::unique_ptr<terrain::GranularGrid> grid_ptr = initial_grid(job, soil);
  terrain::GranularGrid& grid = *grid_ptr;
  const terrain::GridSpec& spec = grid.spec();
  const double initial_centre_m = grid.material_m(spec.nx / 2, spec.ny / 2);

  // Hopper outlet: the cells whose centres lie within its radius (f1), each
  // receiving an equal share of the flow every step (f2).
  const int ci = spec.nx / 2, cj = spec.ny / 2;
  std::vector<std::pair<int, int>> outlet;
  const int reach = static_cast<int>(std::min<double>(std::ceil(job.hopper_radius_m / spec.cell_size_m),
                                                       std::max(spec.nx, spec.ny)));
  for (int dj = -reach; dj <= reach; ++dj)
    for (int di = -reach; di <= reach; ++di)
      if (std::hypot(di, dj) * spec.cell_size_m <= job.hopper_radius_m + 1e-12 && grid.contains(ci + di, cj + dj))
        outlet.emplace_back(ci + di, cj + dj);
  const double volume_per_cell_step =
      job.pour_rate_kg_per_s * job.step_dt_s / soil.bulk_density_kg_m3 / static_cast<double>(outlet.size());

  // Everything is written into a fresh sibling folder, which replaces the run
  // directory only once complete.
  StagedRunDirectory run_dir(job.out_dir, "pour");
  const fs::path staging = run_dir.staging();
  const double total_s = job.pour_duration_s + job.max_settle_s;
  Progress progress("pour", total_s);
  std::int64_t step = 0;
  double settle_s = 0.0;
  std::size_t max_active = 0;
  std::int64_t cell_visits = 0;
  const auto pour_steps = static_cast<std::int64_t>(std::llround(job.pour_duration_s / job.step_dt_s));
  const auto max_steps = pour_steps + static_cast<std::int64_t>(std::llround(job.max_settle_s / job.step_dt_s));
  for (; step < max_steps; ++step) {
    jobs::stop_if_interrupted("pour");
    if (step < pour_steps) {
      try {
        for (const auto& [i, j] : outlet) grid.add_material_m3(i, j, volume_per_cell_step);
      } catch (const std::invalid_argument& e) {
        throw io::InputError(std::string("--rate-kg-s ") + std::to_string(job.pour_rate_kg_per_s) + ": " + e.what());
      }
    } else if (grid.at_rest()) {
      break;
    }
    max_active = std::max(max_active, grid.active_cell_count());
    grid.step();
    cell_visits += grid.last_step().cells_checked;
    const double t = (step + 1) * job.step_dt_s;
    if (step >= pour_steps) settle_s = t - job.pour_duration_s;
    progress.update(t, "active " + std::to_string(grid.active_cell_count()));
  }
  progress.finish();
  const double sim_s = step * job.step_dt_s;
  const double wall_s = progress.wall_seconds();

  const auto surface_info = io::write_heightmap((staging / "terrain_surface").string(), terrain_snapshot(grid, "surface"));
  const auto material_info = io::write_heightmap((staging / "terrain_material").string(), terrain_snapshot(grid, "material"));

  const terrain::PileMetrics pile = terrain::measure_pile(grid, ci, cj, initial_centre_m + 0.005);
  const terrain::MaterialLedger ledger = grid.ledger();
  const terrain::FlowLaw& law = grid.flow_law();
  const double quantum_kg = grid.quantum_mass_kg();
  json summary = {
      {"job", "pour"},
      {"soil", {{"id", soil.name},
                {"bulk_density_kg_m3", soil.bulk_density_kg_m3},
                {"repose_angle_deg", soil.repose_angle_deg},
                {"stop_angle_deg", soil.stop_angle_deg},
                {"rolling_speed_m_per_s", soil.rolling_speed_m_per_s},
                {"rolling_layer_m", soil.rolling_layer_m},
                {"table", table_path}}},
      {"site", {{"size_m", spec.nx * spec.cell_size_m},
                {"cell_size_m", spec.cell_size_m},
                {"nx", spec.nx},
                {"ny", spec.ny},
                {"layer_depth_m", job.layer_depth_m},
                {"material_map", job.material_map_path},
                {"base_map", job.base_map_path},
                {"edges", job.open_edges ? "open" : "closed"}}},
      {"flow_law", {{"z_plus_per_sweep_m", law.z_plus_per_sweep_m},
                    {"z_plus_over_cell", law.z_plus_per_sweep_m / law.cell_size_m},
                    {"stability_bound", terrain::kMaxZPlusOverCell},
                    {"substeps", law.substeps}}},
      {"pour", {{"rate_kg_per_s", job.pour_rate_kg_per_s},
                {"duration_s", job.pour_duration_s},
                {"hopper_radius_m", job.hopper_radius_m},
                {"poured_kg", ledger.added * quantum_kg}}},
      {"result", {{"sim_time_s", sim_s},
                  {"steps", step},
                  {"settle_time_s", settle_s},
                  {"at_rest", grid.at_rest()},
                  {"material_in_cells_kg", ledger.in_cells * quantum_kg},
                  {"off_site_kg", ledger.off_site_total() * quantum_kg},
                  {"ledger_balanced", ledger.balanced()},
                  {"pile_apex_m", pile.apex_material_m},
                  {"pile_radius_axes_m", pile.radius_axes_m},
                  {"pile_radius_diagonals_m", pile.radius_diagonals_m},
                  {"pile_flank_slope_deg", pile.flank_slope_deg}}},
      {"performance", {{"wall_time_s", wall_s},
                       {"real_time_factor", wall_s > 0 ? sim_s / wall_s : 0.0},
                       {"max_active_cells", max_active},
                       {"cell_visits", cell_visits},
                       {"ns_per_cell_visit", cell_visits > 0 ? wall_s * 1e9 / static_cast<double>(cell_visits) : 0.0},
                       {"state_bytes_per_cell", terrain::GranularGrid::kStateBytesPerCell}}},
      {"files", {{"surface", "terrain_surface.png"},
                 {"surface_vertical_scale_m", surface_info.vertical_scale_m},
                 {"material", "terrain_material.png"},
                 {"material_vertical_scale_m", material_info.vertical_scale_m}}},
  };
  io::write_text_atomically((staging / "summary.json").string(), summary.dump(2) + "\n");
  run_dir.commit();

  std::cout << "poured " << summary["pour"]["poured_kg"].get<double>() << " kg of " << soil.name << " on a "
            << spec.nx << " x " << spec.ny << " grid (" << spec.cell_size_m << " m cells); "
            << (grid.at_rest() ? "at rest" : "still moving") << " after " << sim_s << " s simulated in " << wall_s
            << " s (x" << (wall_s > 0 ? sim_s / wall_s : 0.0) << " real time)\n"
            << "pile: apex " << pile.apex_material_m << " m, radius " << pile.radius_axes_m << " m (axes) / "
            << pile.radius_diagonals_m << " m (diagonals), flank " << pile.flank_slope_deg << " deg\n"
            << "wrote " << job.out_dir << "/summary.json and the final terrain height maps\n";
  return 0;
}

}  // namespace skidsim::jobs
