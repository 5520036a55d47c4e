#include "jobs/dig_job.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "jobs/interrupt.h"
#include "jobs/progress.h"
#include "jobs/run_directory.h"
#include "engine/soil_site.h"
#include "engine/world.h"
#include "io/atomic_file.h"
#include "io/loader_files.h"
#include "io/soil_table.h"

namespace skidsim::jobs {

using nlohmann::json;

namespace {

constexpr double kDt = engine::kStepSeconds;

// The scene: the loader at the origin facing +x on firm ground; a soil site
// from x = 1 to 7 m, 6 m wide, holding a bank from x = 2.6 m; a truck bed
// behind the loader (floor 0.9 m up, walls 0.3 m, 1.4 m x 2.5 m, from
// x = -4.3 to -2.9 m).
constexpr double kSiteX0 = 1.0, kSiteLength = 6.0, kSiteWidth = 6.0, kBankFrom = 2.6;
constexpr double kBedX0 = -4.3, kBedLength = 1.4, kBedWidth = 2.5, kBedFloor = 0.9, kBedWall = 0.3;

void require(bool ok, const std::string& option, double value, const std::string& range) {
  if (ok) return;
  std::ostringstream msg;
  msg << option << " " << value << ": expected " << range;
  throw io::InputError(msg.str());
}

double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// The operator's phases; each ends on its goal or its time limit.
enum class Phase { kFill, kCurl, kBackOut, kTurn, kApproach, kRaise, kDump, kBackOff, kSettle, kDone };
const char* phase_name(Phase p) {
  switch (p) {
    case Phase::kFill: return "fill";
    case Phase::kCurl: return "curl";
    case Phase::kBackOut: return "back_out";
    case Phase::kTurn: return "turn";
    case Phase::kApproach: return "approach_truck";
    case Phase::kRaise: return "raise";
    case Phase::kDump: return "dump";
    case Phase::kBackOff: return "back_off";
    case Phase::kSettle: return "settle";
    default: return "done";
  }
}
double phase_limit_s(Phase p) {
  switch (p) {
    case Phase::kFill: return 10.0;
    case Phase::kCurl: return 2.0;
    case Phase::kBackOut: return 6.0;
    case Phase::kTurn: return 10.0;
    case Phase::kApproach: return 8.0;
    case Phase::kRaise: return 4.0;
    case Phase::kDump: return 6.0;
    case Phase::kBackOff: return 4.0;
    default: return 4.0;
  }
}

struct Operator {
  Phase phase = Phase::kFill;
  double phase_start_s = 0.0;
  double fill_end_x = 0.0;
  double dump_x = 0.0;
  double slow_since_s = -1.0;
  double check_kg = 0.0, check_s = 0.0;  // the dump's progress, sampled every 0.5 s
  double tipped_since_s = -1.0;          // the bucket at its full tip since
  std::vector<std::string> timed_out;  // phases that ended on their time limit, not their goal
};

double bucket_pitch(const engine::World& w) { return std::asin(w.bucket_material()->geometric_up().x()); }
double heading(const engine::World& w) {
  const Eigen::Matrix3d r = w.loader().link_pose(0).linear();
  return std::atan2(r(1, 0), r(0, 0));
}
double tilt_to(const engine::World& w, double pitch_rad, double max_lever = 1.0) {
  return std::clamp(6.0 * (bucket_pitch(w) - pitch_rad), -max_lever, max_lever);
}
double lift_to(const engine::World& w, double angle_rad) {
  return std::clamp(4.0 * (angle_rad - w.loader().joint_angle(0)), -1.0, 1.0);
}
Eigen::Vector3d lip(const engine::World& w) {
  const terrain::BodyAutomaton& b = *w.bucket_material();
  return b.world_point(b.grid().nx() - 0.5, 0.5 * (b.grid().ny() - 1), 0.0);
}

// One step of the scripted operator: the controls for this step, and the
// phase moved on when its goal (or time limit) is reached.
vehicle::LoaderControls operate(Operator& op, const engine::World& w, double heaped_kg) {
  vehicle::LoaderControls c;
  const double t = w.time_s(), in_phase = t - op.phase_start_s;
  const Eigen::Vector3d chassis = w.loader().link_pose(0).translation();
  const double speed = w.loader().chassis_velocity().head<2>().norm();
  const bool out_of_time = in_phase > phase_limit_s(op.phase);
  bool done = false;
  switch (op.phase) {
    case Phase::kFill:  // into the bank, bucket level on the ground, until full or stopped
      c.drive_left = c.drive_right = 0.4;
      c.lift = lift_to(w, 0.03);
      c.tilt = tilt_to(w, 0.0);
      if (in_phase > 1.5 && speed < 0.05) {
        if (op.slow_since_s < 0.0) op.slow_since_s = t;
      } else {
        op.slow_since_s = -1.0;
      }
      // Full, stopped by the bank, or at the bank's far end.
      done = w.bucket_material()->material_mass_kg() > 0.9 * heaped_kg ||
             (op.slow_since_s >= 0.0 && t - op.slow_since_s > 0.5) || lip(w).x() > kSiteX0 + kSiteLength - 0.5;
      if (done || out_of_time) op.fill_end_x = chassis.x();
      break;
    case Phase::kCurl:  // break out: curl back while still pushing
      c.drive_left = c.drive_right = 0.15;
      c.tilt = tilt_to(w, 0.35);
      done = bucket_pitch(w) > 0.3;
      break;
    case Phase::kBackOut: {  // reverse 1.5 m raising the arm to 0.9 rad, bucket rolled back
      const bool backed = chassis.x() < op.fill_end_x - 1.5;
      c.drive_left = c.drive_right = backed ? 0.0 : -0.5;
      c.lift = lift_to(w, 0.9);
      c.tilt = tilt_to(w, 0.3);
      done = backed && speed < 0.05 && w.loader().joint_angle(0) > 0.85;
      break;
    }
    case Phase::kTurn: {  // pivot to face -x
      const double e = wrap(kPi - heading(w));
      c.drive_left = std::clamp(-1.5 * e, -0.6, 0.6);
      c.drive_right = -c.drive_left;
      c.lift = lift_to(w, 0.9);
      c.tilt = tilt_to(w, 0.3);
      done = std::abs(e) < 0.03 && std::abs(w.loader().chassis_angular_velocity().z()) < 0.05;
      break;
    }
    case Phase::kApproach: {  // to the truck, the lip 1.1 m over its near wall (raising and
                              // tipping the bucket swing the lip back towards the machine)
      const double e = wrap(kPi - heading(w));
      c.drive_left = 0.3 - std::clamp(1.0 * e, -0.2, 0.2);
      c.drive_right = 0.3 + std::clamp(1.0 * e, -0.2, 0.2);
      c.lift = lift_to(w, 0.9);
      c.tilt = tilt_to(w, 0.3);
      done = lip(w).x() < kBedX0 + kBedLength - 1.1;
      break;
    }
    case Phase::kRaise:  // over the bed: raise to 1.3 rad, floor level
      c.lift = lift_to(w, 1.3);
      c.tilt = tilt_to(w, 0.1);
      done = w.loader().joint_angle(0) > 1.28;
      break;
    case Phase::kDump:  // tip at 60 % lever to 57 deg nose-down until the bucket is empty
      c.lift = lift_to(w, 1.3);
      c.tilt = tilt_to(w, -1.0, 0.6);
      // Empty, or at the full tip with nothing more coming out (what clings
      // in the heel stays).
      {
        const double kg = w.bucket_material()->material_mass_kg();
        if (bucket_pitch(w) < -0.95) {
          if (op.tipped_since_s < 0.0) op.tipped_since_s = t;
        } else {
          op.tipped_since_s = -1.0;
        }
        if (t - op.check_s >= 0.5) {
          const bool stalled = op.tipped_since_s >= 0.0 && t - op.tipped_since_s > 1.5 &&
                               op.check_kg - kg < 0.01 * heaped_kg;
          done = kg < 0.02 * heaped_kg || stalled;
          op.check_kg = kg;
          op.check_s = t;
        }
      }
      op.dump_x = chassis.x();
      break;
    case Phase::kBackOff:  // 1 m back (away from the truck), bucket curled
      c.tilt = tilt_to(w, 0.3);
      c.drive_left = c.drive_right = -0.4;
      done = chassis.x() > op.dump_x + 1.0;
      break;
    case Phase::kSettle:
      c.parking_brake = true;
      done = in_phase > 1.0 && w.material()->parcels().empty();
      break;
    case Phase::kDone:
      c.parking_brake = true;
      break;
  }
  if (out_of_time && !done && op.phase != Phase::kDone) {
    op.timed_out.push_back(phase_name(op.phase));
    if (op.phase == Phase::kFill) op.fill_end_x = chassis.x();
    done = true;
  }
  if (done && op.phase != Phase::kDone) {
    op.phase = static_cast<Phase>(static_cast<int>(op.phase) + 1);
    op.phase_start_s = t + kDt;
    op.slow_since_s = -1.0;
  }
  return c;
}

}  // namespace

int run_dig_job(const DigJob& job) {
  const jobs::InterruptScope interrupt_scope;  // a signal stops the job; the previous result stays
  require(job.cells_per_m >= 10.0 && job.cells_per_m <= 40.0, "--cells-per-m", job.cells_per_m,
          "10 to 40 (the bucket's automaton needs cells of at most 10 cm)");
  require(job.bank_height_m > 0.05 && job.bank_height_m <= 1.5, "--bank-m", job.bank_height_m, "more than 0.05 and at most 1.5 m");
  const std::string table_path = job.soil_table_path.empty() ? io::default_soil_table_path() : job.soil_table_path;
  const io::SoilTable table = io::load_soil_table(table_path);
  const auto it = table.find(job.soil_id);
  if (it == table.end()) throw io::InputError("--soil '" + job.soil_id + "' is not in " + table_path);
  const io::SoilRecord& soil = it->second;
  const std::string loader_path = job.loader_path.empty() ? io::default_loader_path() : job.loader_path;
  const vehicle::LoaderDescription loader = io::load_loader(loader_path);
  if (!loader.bucket_interior.present)
    throw io::InputError(loader_path + ": the bucket has no <interior>: it cannot carry material");

  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0, 0, loader.tyre.radius_m - 0.01);
  engine::World world(loader, engine::FirmGround{}, pose, 0.03, 0.03);
  auto grid = engine::flat_soil_grid(soil.flow, job.cells_per_m, {kSiteX0 + 0.5 / job.cells_per_m, -0.5 * kSiteWidth},
                                     kSiteLength, kSiteWidth, 0.0);
  for (int j = 0; j < grid->ny(); ++j)
    for (int i = 0; i < grid->nx(); ++i)
      if (grid->spec().origin_m.x() + i * grid->cell_size_m() > kBankFrom) grid->set_material_m(i, j, job.bank_height_m);
  world.add_soil_site(std::move(grid), soil.terramechanics);
  engine::TraySpec bed;
  bed.shape.length_m = kBedLength;
  bed.shape.width_m = kBedWidth;
  bed.shape.back_height_m = bed.shape.side_height_back_m = bed.shape.side_height_front_m = bed.shape.front_height_m =
      kBedWall;
  bed.shape.heel_radius_m = 0.0;
  bed.pose.translation() = Eigen::Vector3d(kBedX0, -0.5 * kBedWidth, kBedFloor);
  world.add_tray(bed);

  const terrain::MaterialExchange& ex = *world.material();
  const double q = ex.quantum_mass_kg();
  const double heaped_kg = loader.bucket_interior.heaped_volume_m3 * soil.flow.bulk_density_kg_m3;
  const std::int64_t total = ex.total_quanta();
  bool conserved = true;

  StagedRunDirectory run_dir(job.out_dir, "dig");
  std::ostringstream phases_csv;
  phases_csv << "phase,start_s,end_s,bucket_kg,truck_kg,chassis_x_m,chassis_y_m,heading_deg\n";
  Operator op;
  Phase last = op.phase;
  double last_start = 0.0, bucket_full_kg = 0.0, carried_kg = 0.0, peak_edge_N = 0.0;
  const double limit_s = 60.0;
  Progress progress("dig", limit_s);
  long steps = 0;
  while (op.phase != Phase::kDone && world.time_s() < limit_s) {
    jobs::stop_if_interrupted("dig");
    world.step(operate(op, world, heaped_kg));
    ++steps;
    peak_edge_N = std::max(peak_edge_N, world.edge_penetration_N());
    if (ex.total_quanta() != total) conserved = false;
    if (op.phase != last) {
      const Eigen::Vector3d x = world.loader().link_pose(0).translation();
      const double bucket_kg = world.bucket_material()->material_mass_kg();
      phases_csv << phase_name(last) << "," << last_start << "," << world.time_s() << "," << bucket_kg << ","
                 << world.tray(0).material_mass_kg() << "," << x.x() << "," << x.y() << ","
                 << heading(world) * 180.0 / kPi << "\n";
      if (last == Phase::kCurl) bucket_full_kg = bucket_kg;
      if (last == Phase::kApproach) carried_kg = bucket_kg;
      last = op.phase;
      last_start = world.time_s();
    }
    progress.update(world.time_s(), phase_name(op.phase));
  }
  progress.finish();
  const double wall_s = progress.wall_seconds(), sim_s = world.time_s();

  const double truck_kg = world.tray(0).material_mass_kg();
  const terrain::ExchangeStats& st = ex.stats();
  const auto surface_info = io::write_heightmap((run_dir.staging() / "terrain_surface").string(),
                                                terrain_snapshot(*world.terrain(), "surface"));
  const auto truck_info = io::write_heightmap((run_dir.staging() / "truck_material").string(),
                                              terrain_snapshot(world.tray(0).grid(), "material"));
  io::write_text_atomically((run_dir.staging() / "phases.csv").string(), phases_csv.str());
  const json summary = {
      {"job", "dig"},
      {"soil", {{"id", job.soil_id}, {"bulk_density_kg_m3", soil.flow.bulk_density_kg_m3}, {"table", table_path}}},
      {"loader", {{"parameters", loader_path}, {"bucket_heaped_kg", heaped_kg}}},
      {"site", {{"cells_per_m", job.cells_per_m}, {"bank_height_m", job.bank_height_m}, {"bank_from_x_m", kBankFrom}}},
      {"truck_bed", {{"x_m", {kBedX0, kBedX0 + kBedLength}}, {"width_m", kBedWidth}, {"floor_z_m", kBedFloor},
                     {"wall_m", kBedWall}}},
      {"result",
       {{"completed", op.phase == Phase::kDone && op.timed_out.empty()},
        {"timed_out_phases", op.timed_out},
        {"sliced_kg", st.quanta_sliced * q},
        {"bucket_full_kg", bucket_full_kg},
        // The slicing edge's bearing in an earthmoving soil (0 in the thesis's).
        {"peak_edge_penetration_N", peak_edge_N},
        {"bucket_at_truck_kg", carried_kg},
        {"truck_kg", truck_kg},
        {"left_in_bucket_kg", world.bucket_material()->material_mass_kg()},
        {"spilled_over_lip_kg", st.quanta_over_edge[0] * q},
        {"spilled_over_back_kg", st.quanta_over_edge[1] * q},
        {"spilled_over_sides_kg", (st.quanta_over_edge[2] + st.quanta_over_edge[3]) * q},
        {"into_bucket_over_rims_kg", st.quanta_over_lip * q},
        {"beside_the_site_kg", ex.beside_site_quanta() * q},
        {"in_flight_kg", ex.in_flight_quanta() * q},
        {"material_total_kg", total * q},
        {"material_conserved_every_step", conserved},
        {"machine_finite", world.events().finite},
        {"tipped_over", world.events().tipped_over_s >= 0.0}}},
      {"performance", {{"simulated_s", sim_s},
                       {"wall_time_s", wall_s},
                       {"us_per_step", steps > 0 ? 1e6 * wall_s / static_cast<double>(steps) : 0.0},
                       {"real_time_factor", wall_s > 0 ? sim_s / wall_s : 0.0}}},
      {"files", {{"phases", "phases.csv"},
                 {"surface", "terrain_surface.png"},
                 {"surface_vertical_scale_m", surface_info.vertical_scale_m},
                 {"truck", "truck_material.png"},
                 {"truck_vertical_scale_m", truck_info.vertical_scale_m}}},
  };
  io::write_text_atomically((run_dir.staging() / "summary.json").string(), summary.dump(2) + "\n");
  run_dir.commit();
  std::cout << "dig: filled " << bucket_full_kg << " kg from the bank, carried " << carried_kg << " kg to the truck, "
            << truck_kg << " kg in the truck bed after " << sim_s << " s ("
            << (op.phase == Phase::kDone && op.timed_out.empty() ? "every phase reached its goal"
                                                                  : "some phases ran out of time, see summary.json")
            << "); material "
            << (conserved ? "conserved exactly" : "NOT conserved") << "\nwrote " << job.out_dir
            << "/summary.json, phases.csv and the terrain and truck height maps\n";
  return conserved && world.events().finite ? 0 : 1;
}

}  // namespace skidsim::jobs
