#include "engine/agents.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>

namespace skidsim::engine {
namespace {

constexpr double kNeighbourhoodM = 2.5;   // separation between agents
constexpr double kWaypointM = 0.6;        // a point passed through (not stopped at) counts within this
constexpr double kLoaderMovingMS = 0.2;   // a loader slower than this is standing

double direction(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }
double wrap(double angle) { return std::remainder(angle, 2.0 * kPi); }

// Seek at no more than `speed`.
Eigen::Vector2d seek_at(const SteeringAgent& b, const Eigen::Vector2d& target, double speed) {
  SteeringAgent capped = b;
  capped.max_speed_m_s = std::min(b.max_speed_m_s, speed);
  return seek(capped, target);
}

// Never into the machine, moving or not: away from its footprint's nearest
// point once closer than kPersonClearM.
Eigen::Vector2d avoid_machine(const SteeringAgent& b, const SiteView& site) {
  Eigen::Vector2d nearest;
  const double gap = footprint_distance_m(site, b.position_m, &nearest) - b.radius_m;
  if (gap > kPersonClearM) return Eigen::Vector2d::Zero();
  Eigen::Vector2d away = b.position_m - nearest;
  away = away.norm() > 1e-9 ? Eigen::Vector2d(away.normalized()) : Eigen::Vector2d::UnitY();
  return (away * b.max_speed_m_s - b.velocity_m_s) * (b.mass_kg / kSteeringResponseS);
}

// Prioritised force budget (Reynolds): the first behaviours take what
// they need of the largest force, the later ones what is left.
void add_within_budget(Eigen::Vector2d& total, const Eigen::Vector2d& f, double max_force_N) {
  const double left = max_force_N - total.norm();
  if (left > 0.0) total += truncate(f, left);
}

// Out of a moving loader's way: away from it and, when ahead of it, to the
// side of its path the person already stands on.
Eigen::Vector2d keep_clear(const SteeringAgent& b, const SiteView& site, double clear_m) {
  const Eigen::Vector2d rel = b.position_m - site.loader_m;
  const double d = rel.norm(), speed = site.loader_velocity_m_s.norm();
  if (speed < kLoaderMovingMS || d > clear_m) return Eigen::Vector2d::Zero();
  Eigen::Vector2d away = d > 1e-9 ? Eigen::Vector2d(rel / d) : Eigen::Vector2d::UnitX();
  const Eigen::Vector2d ahead = site.loader_velocity_m_s / speed;
  if (rel.dot(ahead) > 0.0) {
    const Eigen::Vector2d side(-ahead.y(), ahead.x());
    away += (rel.dot(side) >= 0.0 ? 2.0 : -2.0) * side;
    away.normalize();
  }
  return (away * b.max_speed_m_s - b.velocity_m_s) * (b.mass_kg / kSteeringResponseS);
}

// A person's steering, by priority: clear of a moving loader, apart from
// the others, then towards the plan's point (or holding still).
Eigen::Vector2d person_force(const AgentSpec& spec, const AgentState& s, const SiteView& site,
                             const std::vector<SteeringAgent>& everyone, const Eigen::Vector2d* target, bool stop_there) {
  const SteeringAgent& b = s.body;
  Eigen::Vector2d f = Eigen::Vector2d::Zero();
  add_within_budget(f, avoid_machine(b, site), b.max_force_N);
  add_within_budget(f, keep_clear(b, site, spec.keep_clear_m), b.max_force_N);
  add_within_budget(f, separation(b, everyone, kNeighbourhoodM), b.max_force_N);
  if (target) {
    add_within_budget(f, stop_there ? arrive(b, *target, 1.0) : seek(b, *target), b.max_force_N);
  } else {
    add_within_budget(f, arrive(b, b.position_m, 1.0), b.max_force_N);  // stand
  }
  return f;
}

void step_person(const AgentSpec& spec, AgentState& s, const SiteView& site, const std::vector<SteeringAgent>& everyone,
                 double t_s, double dt_s) {
  const int n = static_cast<int>(spec.route_m.size());
  const bool moving = s.phase == AgentPhase::kMoving && s.next_point < n;
  const Eigen::Vector2d* target = moving ? &spec.route_m[static_cast<std::size_t>(s.next_point)] : nullptr;
  const bool last = s.next_point == n - 1 && !spec.loop;
  const bool stop_there = spec.pause_s > 0.0 || last;
  integrate(s.body, person_force(spec, s, site, everyone, target, stop_there), dt_s);
  if (s.body.velocity_m_s.norm() > 0.1) s.heading_rad = direction(s.body.velocity_m_s);
  if (moving) {
    const double d = (s.body.position_m - *target).norm();
    const bool reached = stop_there ? d < kReachedM && s.body.velocity_m_s.norm() < kStoppedMS : d < kWaypointM;
    if (reached) {
      s.next_point = spec.loop ? (s.next_point + 1) % n : s.next_point + 1;
      s.phase = AgentPhase::kPausing;
      s.phase_since_s = t_s;
    }
  } else if (s.phase == AgentPhase::kPausing && s.next_point < n && t_s - s.phase_since_s >= spec.pause_s) {
    s.phase = AgentPhase::kMoving;
    s.phase_since_s = t_s;
  }
}

// The route still to drive from the agent to the end of `points`.
double route_left_m(const Eigen::Vector2d& at, const std::vector<Eigen::Vector2d>& points, int next) {
  double d = (points[static_cast<std::size_t>(next)] - at).norm();
  for (std::size_t k = static_cast<std::size_t>(next) + 1; k < points.size(); ++k) d += (points[k] - points[k - 1]).norm();
  return d;
}

// A truck holds (brakes to a stop) while the machine is within
// kTruckClearM of where the truck is heading: a truck driver waits.
bool loader_in_the_way(const SteeringAgent& b, const Eigen::Vector2d& target, const SiteView& site) {
  const Eigen::Vector2d to = target - b.position_m;
  const double d = to.norm();
  const Eigen::Vector2d dir = d > 1e-9 ? Eigen::Vector2d(to / d) : Eigen::Vector2d::Zero();
  for (double ahead = 0.0; ahead <= std::min(d, 2.0 * kTruckClearM) + 1e-9; ahead += kTruckClearM)
    if (footprint_distance_m(site, b.position_m + dir * ahead) < kTruckRadiusM + kTruckClearM) return true;
  return false;
}

void step_truck(const AgentSpec& spec, AgentState& s, std::size_t k, const SiteView& site, double t_s, double dt_s) {
  SteeringAgent& b = s.body;
  const double brake_m_s2 = b.max_force_N / b.mass_kg;
  if (s.phase == AgentPhase::kMoving) {  // reversing in
    const int n = static_cast<int>(spec.route_m.size());
    const Eigen::Vector2d& target = spec.route_m[static_cast<std::size_t>(s.next_point)];
    const bool last = s.next_point == n - 1;
    // No faster than it can stop in the route left: no overshoot however
    // short the last leg.
    const double left = route_left_m(b.position_m, spec.route_m, s.next_point);
    const double speed = std::sqrt(2.0 * brake_m_s2 * left);
    Eigen::Vector2d f = last ? arrive(b, target, 4.0) : seek_at(b, target, speed);
    if (loader_in_the_way(b, target, site)) f = arrive(b, b.position_m, 1.0);
    integrate(b, f, dt_s);
    if (b.velocity_m_s.norm() > 0.1) s.heading_rad = wrap(direction(b.velocity_m_s) + kPi);
    const double d = (b.position_m - target).norm();
    if (last && d < kReachedM && b.velocity_m_s.norm() < kStoppedMS) {
      s.phase = AgentPhase::kDocked;
      s.docked_at_s = s.phase_since_s = t_s;
      s.heading_rad = spec.dock_heading_rad;  // square to its bed's place
      b.velocity_m_s.setZero();
    } else if (!last && d < 1.0) {
      ++s.next_point;
    }
  } else if (s.phase == AgentPhase::kDocked) {
    b.velocity_m_s.setZero();
    const double load = site.bed_load_kg && k < site.bed_load_kg->size() ? (*site.bed_load_kg)[k] : 0.0;
    if (spec.leave_at_kg > 0.0 && load >= spec.leave_at_kg && !spec.exit_m.empty()) {
      s.phase = AgentPhase::kLeaving;
      s.next_point = 0;
      s.phase_since_s = t_s;
    }
  } else if (s.phase == AgentPhase::kLeaving) {  // forwards, out
    const Eigen::Vector2d& target = spec.exit_m[static_cast<std::size_t>(s.next_point)];
    Eigen::Vector2d f = seek(b, target);
    if (loader_in_the_way(b, target, site)) f = arrive(b, b.position_m, 1.0);
    integrate(b, f, dt_s);
    if (b.velocity_m_s.norm() > 0.1) s.heading_rad = direction(b.velocity_m_s);
    if ((b.position_m - target).norm() < 1.0 && ++s.next_point == static_cast<int>(spec.exit_m.size())) {
      s.phase = AgentPhase::kGone;
      s.phase_since_s = t_s;
    }
  }
}

}  // namespace

double footprint_distance_m(const SiteView& site, const Eigen::Vector2d& p, Eigen::Vector2d* nearest) {
  const Eigen::Vector2d a = site.loader_rear_m, ab = site.loader_front_m - site.loader_rear_m;
  const double u = ab.squaredNorm() > 0.0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  const Eigen::Vector2d on_axis = a + u * ab;
  const Eigen::Vector2d out = p - on_axis;
  const double d = out.norm();
  if (nearest) *nearest = d > 1e-9 ? Eigen::Vector2d(on_axis + out * (std::min(site.loader_half_width_m, d) / d)) : on_axis;
  return std::max(0.0, d - site.loader_half_width_m);
}

std::vector<AgentState> start_agents(const std::vector<AgentSpec>& specs) {
  std::vector<AgentState> states(specs.size());
  for (std::size_t k = 0; k < specs.size(); ++k) {
    const AgentSpec& spec = specs[k];
    AgentState& s = states[k];
    const bool truck = spec.kind == AgentKind::kTruck;
    s.body.mass_kg = truck ? kTruckMassKg : kPersonMassKg;
    s.body.radius_m = truck ? kTruckRadiusM : kPersonRadiusM;
    s.body.max_speed_m_s = spec.speed_m_s;
    s.body.max_force_N = s.body.mass_kg * (truck ? 1.5 : 2.5);  // m/s^2 a truck and a person manage
    if (!spec.route_m.empty()) s.body.position_m = spec.route_m.front();
    if (spec.route_m.size() > 1) s.heading_rad = wrap(direction(spec.route_m[1] - spec.route_m[0]) + (truck ? kPi : 0.0));
    if (truck && spec.route_m.size() == 1) s.heading_rad = spec.dock_heading_rad;
  }
  return states;
}

void step_agents(const std::vector<AgentSpec>& specs, std::vector<AgentState>& states, const SiteView& site, double t_s,
                 double dt_s, std::vector<SteeringAgent>& scratch) {
  scratch.resize(states.size());
  for (std::size_t k = 0; k < states.size(); ++k) {
    scratch[k] = states[k].body;
    if (!on_site(states[k])) scratch[k].position_m = Eigen::Vector2d::Constant(1e9);  // out of everyone's reach
  }
  for (std::size_t k = 0; k < states.size(); ++k) {
    const AgentSpec& spec = specs[k];
    AgentState& s = states[k];
    if (s.phase == AgentPhase::kNotYet) {
      if (spec.held || t_s < spec.start_s || spec.route_m.empty()) continue;
      s.phase = spec.route_m.size() > 1 ? AgentPhase::kMoving : AgentPhase::kPausing;
      s.next_point = 1;
      s.phase_since_s = t_s;
      if (spec.kind == AgentKind::kTruck && spec.route_m.size() == 1) {
        s.phase = AgentPhase::kDocked;
        s.docked_at_s = t_s;
      }
    }
    if (!on_site(s)) continue;
    if (spec.kind == AgentKind::kPerson) {
      step_person(spec, s, site, scratch, t_s, dt_s);
    } else {
      step_truck(spec, s, k, site, t_s, dt_s);
    }
  }
}

}  // namespace skidsim::engine
