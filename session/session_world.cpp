#include "session/session_world.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>

#include "io/atomic_file.h"

namespace skidsim::session {
namespace {

constexpr int kMaxSettlingSteps = 30000;  // 60 s of avalanching at 2 ms

// Distance from p to the segment a-b.
double distance_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = ab.squaredNorm() > 0.0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// The soil site's grid: the layer, minus the trenches, plus the banks and
// the piles (cones), on a flat hard base at z = 0.
std::unique_ptr<terrain::GranularGrid> soil_grid(const io::SoilSite& s, const terrain::SoilFlowParameters& flow) {
  terrain::GridSpec spec;
  spec.cell_size_m = s.cell_m;
  spec.nx = static_cast<int>(std::lround(s.region.sizes().x() / s.cell_m));
  spec.ny = static_cast<int>(std::lround(s.region.sizes().y() / s.cell_m));
  spec.origin_m = s.region.min() + Eigen::Vector2d::Constant(0.5 * s.cell_m);
  auto g = std::make_unique<terrain::GranularGrid>(spec, flow, engine::kStepSeconds);
  for (int j = 0; j < spec.ny; ++j)
    for (int i = 0; i < spec.nx; ++i) {
      const Eigen::Vector2d p = spec.origin_m + s.cell_m * Eigen::Vector2d(i, j);
      double h = s.depth_m;
      for (const io::SoilTrench& t : s.trenches)
        if (distance_to_segment(p, t.from_m, t.to_m) <= 0.5 * t.width_m) h = std::min(h, s.depth_m - t.depth_m);
      for (const io::SoilBank& b : s.banks)
        if (b.region.contains(p)) h += b.height_m;
      for (const io::SoilSlope& r : s.slopes)
        if (r.region.contains(p)) {
          const int a = r.rising_axis;
          const double f = (p[a] - r.region.min()[a]) / r.region.sizes()[a];
          h += r.height_m * (r.rising_up ? f : 1.0 - f);
        }
      for (const io::SoilPile& c : s.piles) h += c.height_m * std::max(0.0, 1.0 - (p - c.centre_m).norm() / c.radius_m);
      g->set_material_m(i, j, std::max(0.0, h));
    }
  return g;
}

}  // namespace

std::unique_ptr<engine::World> build_session_world(const io::Exercise& ex, const vehicle::LoaderDescription& loader,
                                                   const io::SoilTable& soils) {
  if (ex.soils.size() > 1)
    throw io::InputError(ex.path + ": this version builds one <soil> per exercise; it has " +
                         std::to_string(ex.soils.size()));
  engine::FirmGround ground;
  ground.has_plane = ex.firm_ground;
  for (const io::BoxObstacle& b : ex.boxes) {
    engine::StaticBox box;
    box.pose.linear() = Eigen::AngleAxisd(b.yaw_deg * kPi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    box.pose.translation() = b.centre_m;
    box.half_extents_m = 0.5 * b.size_m;
    ground.boxes.push_back(box);
  }
  // The machine on its wheels at its start: on the soil's surface there.
  std::unique_ptr<terrain::GranularGrid> grid;
  double ground_z = 0.0;
  if (!ex.soils.empty()) {
    const io::SoilSite& s = ex.soils.front();
    terrain::SoilFlowParameters flow = soils.at(s.soil).flow;
    flow.model = s.model;
    grid = soil_grid(s, flow);
    // The site as the trainee finds it: what the exercise describes, settled.
    // Loose soil cannot stand in a trench's or bank's vertical walls; letting
    // it slump before the start keeps that slumping out of the tasks'
    // baselines (a trench would otherwise "backfill" itself).
    for (int k = 0; k < kMaxSettlingSteps && !grid->at_rest(); ++k) grid->step();
    if (s.region.contains(ex.machine.position_m)) {
      const Eigen::Vector2d ij = (ex.machine.position_m - grid->spec().origin_m) / s.cell_m;
      const int i = std::clamp(static_cast<int>(std::lround(ij.x())), 0, grid->nx() - 1);
      const int j = std::clamp(static_cast<int>(std::lround(ij.y())), 0, grid->ny() - 1);
      ground_z = grid->surface_m(i, j);
    }
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(ex.machine.yaw_deg * kPi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(ex.machine.position_m.x(), ex.machine.position_m.y(),
                                       ground_z + loader.tyre.radius_m - 0.01);
  auto world = std::make_unique<engine::World>(loader, ground, pose, ex.machine.lift_rad, ex.machine.tilt_rad);
  if (grid) {
    world->add_soil_site(std::move(grid), soils.at(ex.soils.front().soil).terramechanics);
    if (ex.soils.front().fast_flow) world->enable_fast_flow(terrain::session_flow_parameters());
  } else if (!ex.trucks.empty() || loader.bucket_interior.present) {
    // No soil on site: the bucket and the beds still carry what they get.
    world->enable_material(soils.count("dry_sand") ? soils.at("dry_sand").flow : terrain::SoilFlowParameters{}, 0.05);
  }
  for (const io::TruckBed& t : ex.trucks) {
    engine::TraySpec bed;
    bed.pose.linear() = Eigen::AngleAxisd(t.yaw_deg * kPi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    bed.pose.translation() = Eigen::Vector3d(t.back_corner_m.x(), t.back_corner_m.y(), t.floor_height_m);
    bed.shape.length_m = t.length_m;
    bed.shape.width_m = t.width_m;
    bed.shape.back_height_m = bed.shape.side_height_back_m = bed.shape.side_height_front_m = bed.shape.front_height_m =
        t.wall_height_m;
    bed.shape.heel_radius_m = 0.0;
    world->add_tray(bed);
  }
  // People and trucks (after the beds a truck carries).
  for (const io::SiteAgent& g : ex.agents) {
    engine::AgentSpec a;
    a.id = g.id;
    a.kind = g.kind == io::SiteAgent::Kind::kTruck ? engine::AgentKind::kTruck : engine::AgentKind::kPerson;
    a.route_m = g.route_m;
    a.loop = g.loop;
    a.pause_s = g.pause_s;
    a.start_s = g.start_s;
    a.held = !g.start_after.empty();  // released by the session when its task is done
    a.speed_m_s = g.speed_m_s;
    a.keep_clear_m = g.keep_clear_m;
    a.leave_at_kg = g.leave_at_kg;
    a.exit_m = g.exit_m;
    for (std::size_t t = 0; t < ex.trucks.size(); ++t)
      if (ex.trucks[t].id == g.bed) a.tray = static_cast<int>(t);
    world->add_agent(a);
  }
  return world;
}

skidsim_lcm::state_t machine_state(const engine::World& w, bool controls_neutral) {
  const vehicle::Loader& l = w.loader();
  skidsim_lcm::state_t s{};
  s.step = w.steps();
  s.sim_time_s = w.time_s();
  const Eigen::Isometry3d chassis = l.link_pose(0);
  const Eigen::Quaterniond q(chassis.linear());
  for (int k = 0; k < 3; ++k) s.chassis_position_m[k] = chassis.translation()[k];
  s.chassis_orientation_wxyz[0] = q.w();
  s.chassis_orientation_wxyz[1] = q.x();
  s.chassis_orientation_wxyz[2] = q.y();
  s.chassis_orientation_wxyz[3] = q.z();
  const Eigen::Vector3d v = l.chassis_velocity(), omega = l.chassis_angular_velocity();
  for (int k = 0; k < 3; ++k) {
    s.chassis_velocity_m_s[k] = v[k];
    s.chassis_angular_velocity_rad_s[k] = omega[k];
  }
  s.lift_angle_rad = l.joint_angle(0);
  s.tilt_angle_rad = l.joint_angle(1);
  {
    // The floor's x axis in the world: the bucket link's x (the container
    // frame has its axes).
    const Eigen::Matrix3d r = l.link_pose(static_cast<int>(l.description().links.size()) - 1).linear();
    s.bucket_pitch_rad = std::asin(std::clamp(r(2, 0), -1.0, 1.0));
  }
  s.lift_pressure_Pa = l.cylinders().size() > 0 ? l.cylinders()[0].pressure_Pa : 0.0;
  s.tilt_pressure_Pa = l.cylinders().size() > 1 ? l.cylinders()[1].pressure_Pa : 0.0;
  const auto& wheels = l.wheels();
  s.num_wheels = static_cast<std::int8_t>(wheels.size());
  for (std::size_t k = 0; k < wheels.size(); ++k) {
    s.wheel_speed_rad_s.push_back(l.side_wheel_speed(l.description().wheels[k].side));
    s.wheel_slip.push_back(wheels[k].slip_ratio);
  }
  const vehicle::Loader::AxleLoads axles = l.axle_loads();
  s.engine_speed_rpm = l.engine_speed_rpm();
  s.bucket_payload_kg = w.bucket_material() ? w.bucket_material()->material_mass_kg() : 0.0;
  s.tipping_margin = axles.total_N > 0.0 ? axles.rear_N / axles.total_N : 0.0;
  s.controls_neutral = controls_neutral;
  s.active_task = "";
  s.score = 0.0;
  const std::vector<engine::AgentState>& agents = w.agents();
  s.num_agents = static_cast<std::int16_t>(agents.size());
  for (std::size_t k = 0; k < agents.size(); ++k) {
    const engine::AgentState& a = agents[k];
    s.agent_id.push_back(w.agent_specs()[k].id);
    s.agent_kind.push_back(w.agent_specs()[k].kind == engine::AgentKind::kTruck ? 1 : 0);
    s.agent_phase.push_back(static_cast<std::int8_t>(a.phase));
    s.agent_position_m.push_back({a.body.position_m.x(), a.body.position_m.y()});
    s.agent_heading_rad.push_back(a.heading_rad);
  }
  return s;
}

}  // namespace skidsim::session
