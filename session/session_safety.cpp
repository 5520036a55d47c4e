#include "session/session_safety.h"

#include <algorithm>
#include <cmath>

namespace skidsim::session {

double distance_to_machine_m(const engine::World& world, const Eigen::Vector2d& p) {
  const vehicle::Loader& l = world.loader();
  const Eigen::Isometry3d chassis = l.link_pose(0);
  const Eigen::Vector2d a = (chassis * Eigen::Vector3d(-1.3, 0.0, 0.0)).head<2>();
  const int bucket = static_cast<int>(l.description().links.size()) - 1;
  const Eigen::Vector2d b = (l.link_pose(bucket) * Eigen::Vector3d(0.5, 0.0, 0.0)).head<2>();
  const Eigen::Vector2d ab = b - a;
  const double u = ab.squaredNorm() > 0.0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return std::max(0.0, (a + u * ab - p).norm() - kMachineHalfWidthM);
}

void SafetyMonitor::update(const engine::World& world, double t_s, double dt_s, const Emit& emit) {
  const std::vector<engine::AgentSpec>& specs = world.agent_specs();
  const std::vector<engine::AgentState>& agents = world.agents();
  if (specs.empty()) return;
  apart_s_.resize(specs.size(), 1e9);
  touching_.resize(specs.size(), false);
  near_.resize(specs.size(), false);
  near_hit_.resize(specs.size(), false);
  near_gap_m_.resize(specs.size(), 1e9);
  world.agents_touching_machine(touching_now_);
  const double speed = world.loader().chassis_velocity().head<2>().norm();
  const bool moving = speed > 0.2;
  bool someone_near = false;
  for (std::size_t k = 0; k < specs.size(); ++k) {
    // Bullet's contacts (the chassis, the bucket, a truck's parts), or a
    // person inside the machine's footprint: the wheels are probes, not
    // colliders, so a wheel over a foot shows only here.
    const bool inside = specs[k].kind == engine::AgentKind::kPerson && engine::on_site(agents[k]) &&
                        distance_to_machine_m(world, agents[k].body.position_m) <= engine::kPersonRadiusM;
    const bool touching =
        inside || std::find(touching_now_.begin(), touching_now_.end(), static_cast<int>(k)) != touching_now_.end();
    apart_s_[k] = touching ? 0.0 : apart_s_[k] + dt_s;
    const bool person = specs[k].kind == engine::AgentKind::kPerson;
    // A contact that lasts counts once; a new one after 1 s clear.
    if (touching && !touching_[k]) {
      (person ? metrics_.people_collisions : metrics_.truck_collisions) += 1.0;
      emit(t_s, "collision", std::string("the machine hit ") + (person ? "person '" : "truck '") + specs[k].id + "'", 2);
    }
    if (touching) touching_[k] = true;
    if (touching_[k] && apart_s_[k] >= 1.0) touching_[k] = false;
    if (!person || !engine::on_site(agents[k])) continue;
    const double gap = std::max(0.0, distance_to_machine_m(world, agents[k].body.position_m) - engine::kPersonRadiusM);
    someone_near = someone_near || gap < kNearPeopleM;
    if (moving) metrics_.min_distance_to_people_m = std::min(metrics_.min_distance_to_people_m, gap);
    // A near miss: the moving machine came closer than kNearMissM and the
    // person got away (twice as far) without being touched; counted when
    // they are clear, with the closest gap of that pass.
    if (moving && gap < kNearMissM) near_[k] = true;
    if (near_[k]) {
      near_gap_m_[k] = std::min(near_gap_m_[k], gap);
      near_hit_[k] = near_hit_[k] || touching;
      if (gap > 2.0 * kNearMissM) {
        if (!near_hit_[k]) {
          metrics_.near_misses += 1.0;
          emit(t_s, "near_miss", "the machine passed within " + std::to_string(std::lround(near_gap_m_[k] * 100.0)) +
                                     " cm of person '" + specs[k].id + "'", 1);
        }
        near_[k] = near_hit_[k] = false;
        near_gap_m_[k] = 1e9;
      }
    }
  }
  if (someone_near && speed > kWalkingPaceMS) metrics_.speed_near_people_s += dt_s;
}

}  // namespace skidsim::session
