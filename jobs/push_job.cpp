#include "jobs/push_job.h"
#include "common/physical_constants.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "jobs/interrupt.h"
#include "jobs/progress.h"
#include "jobs/run_directory.h"
#include "io/atomic_file.h"
#include "io/soil_table.h"
#include "terrain/body_shapes.h"
#include "terrain/earthmoving.h"
#include "terrain/soil_contact.h"

namespace skidsim::jobs {

using nlohmann::json;

namespace {

void require(bool ok, const std::string& option, double value, const std::string& range) {
  if (ok) return;
  std::ostringstream msg;
  msg << option << " " << value << ": expected " << range;
  throw io::InputError(msg.str());
}

}  // namespace

int run_push_job(const PushJob& job) {
  const jobs::InterruptScope interrupt_scope;  // a signal stops the job; the previous result stays
  require(job.cells_per_m >= 2.0 && job.cells_per_m <= 200.0, "--cells-per-m", job.cells_per_m, "2 to 200");
  require(job.layer_m > 0.0 && job.layer_m <= 10.0, "--layer-m", job.layer_m, "more than 0 and at most 10 m");
  require(job.depth_m > 0.0 && job.depth_m < job.layer_m, "--depth-m", job.depth_m,
          "more than 0 and less than the layer (--layer-m)");
  require(job.width_m >= 2.0 / job.cells_per_m && job.width_m <= 10.0, "--width-m", job.width_m,
          "at least two cells and at most 10 m");
  require(job.rake_deg >= 10.0 && job.rake_deg <= 90.0, "--rake-deg", job.rake_deg, "10 to 90 deg");
  terrain::CuttingModel chosen = terrain::CuttingModel::kThesisWedge;
  if (!job.cutting_model.empty() && !terrain::cutting_model_from_name(job.cutting_model, &chosen))
    throw io::InputError("--cutting-model '" + job.cutting_model + "': expected earthmoving or thesis_wedge");
  require(job.speed_m_s >= 0.01 && job.speed_m_s <= 10.0, "--speed-m-s", job.speed_m_s, "0.01 to 10 m/s");
  require(job.distance_m > 0.0 && job.distance_m <= 100.0, "--distance-m", job.distance_m, "more than 0 and at most 100 m");
  require(job.distance_m / job.speed_m_s <= 600.0, "--distance-m", job.distance_m,
          "a push of at most 600 s at --speed-m-s");
  const double cells = (job.distance_m + 3.0) * job.cells_per_m * (job.width_m + 3.0) * job.cells_per_m;
  require(cells <= 4.0e7, "--cells-per-m", job.cells_per_m, "a site of at most 4e7 cells for this push");

  const std::string table_path = job.soil_table_path.empty() ? io::default_soil_table_path() : job.soil_table_path;
  const io::SoilTable table = io::load_soil_table(table_path);
  const auto it = table.find(job.soil_id);
  if (it == table.end()) throw io::InputError("--soil '" + job.soil_id + "' is not in " + table_path);
  io::SoilRecord soil = it->second;
  if (!job.cutting_model.empty()) soil.terramechanics.cutting = chosen;
  const bool earthmoving = soil.terramechanics.cutting == terrain::CuttingModel::kEarthmoving;

  // The site: a strip a blade length wider than the blade on each side, the
  // push plus 3 m long; cell (0, 0) centred at (d/2, d/2).
  terrain::GridSpec spec;
  spec.cell_size_m = 1.0 / job.cells_per_m;
  spec.nx = static_cast<int>(std::lround((job.distance_m + 3.0) * job.cells_per_m));
  spec.ny = static_cast<int>(std::lround((job.width_m + 3.0) * job.cells_per_m));
  spec.origin_m = {0.5 * spec.cell_size_m, 0.5 * spec.cell_size_m};
  terrain::GranularGrid grid(spec, soil.flow, job.step_dt_s);
  for (int j = 0; j < spec.ny; ++j)
    for (int i = 0; i < spec.nx; ++i) grid.set_material_m(i, j, job.layer_m);
  terrain::SoilContactModel model(grid, soil.terramechanics);

  // The blade: a block at least two cells thick, its +x face the blade,
  // started in its slot (the soil its volume overlaps taken out). A raked
  // blade is the same block with its face declared at the rake (the face's
  // normal (sin(rake), 0, cos(rake))): the 2.5-D grid cannot hold soil on a
  // raked face, and the block sweeps the same section, depth by width, as a
  // raked blade of that depth; the rake enters through the earthmoving
  // equation.
  const double rake = deg_to_rad(job.rake_deg);
  terrain::OrientedBox blade;
  blade.half_extents_m = {std::max(0.15, spec.cell_size_m), 0.5 * job.width_m, 0.5 * job.layer_m + 0.2};
  const double x_start = 1.0;
  blade.centre_m = {x_start, 0.5 * spec.ny * spec.cell_size_m + 1e-3,
                    job.layer_m - job.depth_m + blade.half_extents_m.z()};
  if (job.rake_deg < 90.0) model.set_tool_face(0, Eigen::Vector3d(std::sin(rake), 0.0, std::cos(rake)));
  {
    terrain::ContactMapper mapper;
    terrain::ContactMap map;
    mapper.build(grid, blade, terrain::BodyMotion{}, &map);
    const double d = spec.cell_size_m;
    for (const terrain::CellContact& c : map.cells)
      grid.remove_material_m3(c.i, c.j, c.covered_fraction * d * d * c.depth_m);
  }
  terrain::BodyMotion motion;
  motion.linear_velocity_m_s = {job.speed_m_s, 0.0, 0.0};
  motion.reference_point_m = blade.centre_m;
  model.embed(0, blade, motion);

  const double phi = deg_to_rad(soil.terramechanics.friction_angle_deg);
  const terrain::WedgeSolution flat =
      terrain::flat_ground_wedge(phi, soil.flow.bulk_density_kg_m3, job.depth_m, job.width_m);
  // The earthmoving equation on flat ground (McKyes and Ali), evaluated
  // from the soil table's parameters.
  const terrain::CuttingSoil cutting = terrain::cutting_soil(soil.terramechanics, soil.flow.bulk_density_kg_m3);
  terrain::CuttingTool tool;
  tool.depth_m = job.depth_m;
  tool.width_m = job.width_m;
  tool.rake_rad = rake;
  const terrain::CuttingForce equation = terrain::mckyes_ali(cutting, tool);
  const double gamma_d2_w = cutting.unit_weight_N_per_m3 * job.depth_m * job.depth_m * job.width_m;

  StagedRunDirectory run_dir(job.out_dir, "push");
  std::ostringstream csv;
  csv << "distance_m,resistance_N,wedge_weight_N,wedge_depth_m,displaced_m3,vertical_force_N,face_vertical_down_N\n";
  csv << std::setprecision(9);
  const auto steps = static_cast<std::int64_t>(std::llround(job.distance_m / job.speed_m_s / job.step_dt_s));
  const auto record_every = std::max<std::int64_t>(1, std::llround(0.02 / job.speed_m_s / job.step_dt_s));
  Progress progress("push", steps * job.step_dt_s);
  double displaced_m3 = 0.0, first_N = 0.0, last_N = 0.0;
  for (std::int64_t k = 0; k <= steps; ++k) {
    jobs::stop_if_interrupted("push");
    if (k > 0) blade.centre_m.x() += job.speed_m_s * job.step_dt_s;
    motion.reference_point_m = blade.centre_m;
    const terrain::BodyReaction r = model.interact(0, blade, motion);
    grid.step();
    displaced_m3 += r.displaced_m3;
    if (k == 0) first_N = r.wedge[0].bound_N;
    last_N = r.wedge[0].bound_N;
    if (k % record_every == 0 || k == steps) {
      csv << blade.centre_m.x() - x_start << "," << r.wedge[0].bound_N << "," << r.wedge[0].weight_N << ","
          << r.wedge[0].depth_m << "," << displaced_m3 << "," << r.force_N.z() << "," << r.wedge[0].vertical_down_N
          << "\n";
    }
    progress.update((k + 1) * job.step_dt_s, "resistance " + std::to_string(static_cast<long>(last_N)) + " N");
  }
  progress.finish();
  const double wall_s = progress.wall_seconds();
  const double sim_s = steps * job.step_dt_s;

  io::write_text_atomically((run_dir.staging() / "resistance.csv").string(), csv.str());
  const auto surface_info =
      io::write_heightmap((run_dir.staging() / "terrain_surface").string(), terrain_snapshot(grid, "surface"));
  const terrain::MaterialLedger ledger = grid.ledger();
  const json summary = {
      {"job", "push"},
      {"soil", {{"id", job.soil_id},
                {"friction_angle_deg", soil.terramechanics.friction_angle_deg},
                {"bulk_density_kg_m3", soil.flow.bulk_density_kg_m3},
                {"table", table_path}}},
      {"site", {{"nx", spec.nx}, {"ny", spec.ny}, {"cell_size_m", spec.cell_size_m}, {"layer_m", job.layer_m}}},
      {"blade", {{"depth_m", job.depth_m}, {"width_m", job.width_m}, {"rake_deg", job.rake_deg},
                 {"speed_m_s", job.speed_m_s}, {"distance_m", job.distance_m}}},
      {"cutting_model", terrain::cutting_model_name(soil.terramechanics.cutting)},
      {"reference",
       {{"earthmoving_N", equation.horizontal_N},
        {"earthmoving_terms_N",
         {{"weight", equation.weight_term_N},
          {"cohesion", equation.cohesion_term_N},
          {"surcharge", equation.surcharge_term_N},
          {"adhesion", equation.adhesion_term_N}}},
        {"earthmoving_vertical_down_N", equation.vertical_down_N},
        {"earthmoving_beta_deg", rad_to_deg(equation.failure_angle_rad)},
        {"earthmoving_N_over_gamma_d2_w", gamma_d2_w > 0.0 ? equation.horizontal_N / gamma_d2_w : 0.0},
        {"flat_ground_wedge_N", flat.force_N},
        {"rho_deg", rad_to_deg(flat.rho_rad)}}},
      {"result", {{"resistance_at_start_N", first_N},
                  {"start_over_gamma_d2_w", gamma_d2_w > 0.0 ? first_N / gamma_d2_w : 0.0},
                  {"resistance_at_end_N", last_N},
                  {"displaced_m3", displaced_m3},
                  {"ledger_balanced", ledger.balanced()},
                  {"material_in_cells_kg", ledger.in_cells * grid.quantum_mass_kg()}}},
      {"performance", {{"wall_time_s", wall_s},
                       {"us_per_step", steps > 0 ? 1e6 * wall_s / static_cast<double>(steps + 1) : 0.0},
                       {"real_time_factor", wall_s > 0 ? sim_s / wall_s : 0.0}}},
      {"files", {{"resistance", "resistance.csv"},
                 {"surface", "terrain_surface.png"},
                 {"surface_vertical_scale_m", surface_info.vertical_scale_m}}},
  };
  io::write_text_atomically((run_dir.staging() / "summary.json").string(), summary.dump(2) + "\n");
  run_dir.commit();
  std::cout << "pushed a " << job.width_m << " m blade at rake " << job.rake_deg << " deg " << job.distance_m
            << " m at " << job.depth_m << " m deep in " << job.soil_id << " ("
            << (earthmoving ? "earthmoving equation" : "thesis wedge") << "): resistance " << first_N
            << " N at the start, " << last_N << " N at the end; " << displaced_m3 << " m^3 pushed\n"
            << "earthmoving equation on flat ground: " << equation.horizontal_N << " N = weight "
            << equation.weight_term_N << " + cohesion " << equation.cohesion_term_N << " + adhesion "
            << equation.adhesion_term_N << " N (beta " << rad_to_deg(equation.failure_angle_rad)
            << " deg); thesis wedge " << flat.force_N << " N\n"
            << "wrote " << job.out_dir << "/summary.json, resistance.csv and the final terrain height map\n";
  return 0;
}

}  // namespace skidsim::jobs
