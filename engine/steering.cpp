#include "engine/steering.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace skidsim::engine {
namespace {

// The force that changes the velocity by dv over the response time.
Eigen::Vector2d force_for(const SteeringAgent& a, const Eigen::Vector2d& dv) { return dv * (a.mass_kg / kSteeringResponseS); }

}  // namespace

Eigen::Vector2d truncate(const Eigen::Vector2d& v, double max) {
  const double n = v.norm();
  return n > max && n > 0.0 ? Eigen::Vector2d(v * (max / n)) : v;
}

Eigen::Vector2d seek(const SteeringAgent& a, const Eigen::Vector2d& target_m) {
  const Eigen::Vector2d to = target_m - a.position_m;
  const double d = to.norm();
  const Eigen::Vector2d desired = d > 1e-9 ? Eigen::Vector2d(to * (a.max_speed_m_s / d)) : Eigen::Vector2d::Zero();
  return force_for(a, desired - a.velocity_m_s);
}

Eigen::Vector2d flee(const SteeringAgent& a, const Eigen::Vector2d& threat_m, double panic_m) {
  const Eigen::Vector2d away = a.position_m - threat_m;
  const double d = away.norm();
  if (d > panic_m) return Eigen::Vector2d::Zero();
  const Eigen::Vector2d dir = d > 1e-9 ? Eigen::Vector2d(away / d) : Eigen::Vector2d::UnitX();
  return force_for(a, dir * a.max_speed_m_s - a.velocity_m_s);
}

Eigen::Vector2d arrive(const SteeringAgent& a, const Eigen::Vector2d& target_m, double slowing_m) {
  const Eigen::Vector2d to = target_m - a.position_m;
  const double d = to.norm();
  if (d < 1e-6) return force_for(a, -a.velocity_m_s);
  // Ramped speed inside the slowing distance, and never faster than the
  // largest force can stop in the distance left: v^2 = 2 (F / m) d.
  const double stop_speed = std::sqrt(2.0 * a.max_force_N / a.mass_kg * d);
  const double speed = std::min({a.max_speed_m_s, a.max_speed_m_s * d / std::max(slowing_m, 1e-6), stop_speed});
  return force_for(a, to * (speed / d) - a.velocity_m_s);
}

Eigen::Vector2d pursue(const SteeringAgent& a, const Eigen::Vector2d& target_m, const Eigen::Vector2d& target_velocity_m_s) {
  const double ahead_s = (target_m - a.position_m).norm() / std::max(a.max_speed_m_s, 1e-6);
  return seek(a, target_m + target_velocity_m_s * ahead_s);
}

Eigen::Vector2d evade(const SteeringAgent& a, const Eigen::Vector2d& threat_m, const Eigen::Vector2d& threat_velocity_m_s,
                      double panic_m) {
  const double ahead_s = (threat_m - a.position_m).norm() / std::max(a.max_speed_m_s, 1e-6);
  return flee(a, threat_m + threat_velocity_m_s * ahead_s, panic_m);
}

Eigen::Vector2d separation(const SteeringAgent& a, const std::vector<SteeringAgent>& others, double neighbourhood_m) {
  Eigen::Vector2d push = Eigen::Vector2d::Zero();
  for (const SteeringAgent& o : others) {
    const Eigen::Vector2d away = a.position_m - o.position_m;
    const double d = away.norm();
    if (d < 1e-9 || d > neighbourhood_m) continue;  // itself, or out of reach
    // Inverse to the gap between their edges, so that touching repels hard.
    const double gap = std::max(d - a.radius_m - o.radius_m, 0.05);
    push += away / d / gap;
  }
  return truncate(push * a.max_force_N, a.max_force_N);
}

Eigen::Vector2d cohesion(const SteeringAgent& a, const std::vector<SteeringAgent>& others, double neighbourhood_m) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int n = 0;
  for (const SteeringAgent& o : others) {
    const double d = (o.position_m - a.position_m).norm();
    if (d < 1e-9 || d > neighbourhood_m) continue;
    sum += o.position_m;
    ++n;
  }
  return n == 0 ? Eigen::Vector2d::Zero() : seek(a, sum / n);
}

Eigen::Vector2d alignment(const SteeringAgent& a, const std::vector<SteeringAgent>& others, double neighbourhood_m) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int n = 0;
  for (const SteeringAgent& o : others) {
    const double d = (o.position_m - a.position_m).norm();
    if (d < 1e-9 || d > neighbourhood_m) continue;
    sum += o.velocity_m_s;
    ++n;
  }
  return n == 0 ? Eigen::Vector2d::Zero() : force_for(a, sum / n - a.velocity_m_s);
}

double path_length_m(const Path& path) {
  double s = 0.0;
  for (std::size_t k = 1; k < path.points_m.size(); ++k) s += (path.points_m[k] - path.points_m[k - 1]).norm();
  return s;
}

double path_distance_m(const Path& path, const Eigen::Vector2d& p) {
  double best = 0.0, best_d2 = std::numeric_limits<double>::infinity(), along = 0.0;
  for (std::size_t k = 1; k < path.points_m.size(); ++k) {
    const Eigen::Vector2d a = path.points_m[k - 1], b = path.points_m[k];
    const double len = (b - a).norm();
    const double t = len > 0.0 ? std::clamp((p - a).dot(b - a) / (len * len), 0.0, 1.0) : 0.0;
    const double d2 = (a + t * (b - a) - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = along + t * len;
    }
    along += len;
  }
  return best;
}

Eigen::Vector2d path_point_m(const Path& path, double distance_m) {
  if (path.points_m.empty()) return Eigen::Vector2d::Zero();
  double along = 0.0;
  for (std::size_t k = 1; k < path.points_m.size(); ++k) {
    const Eigen::Vector2d a = path.points_m[k - 1], b = path.points_m[k];
    const double len = (b - a).norm();
    if (along + len >= distance_m && len > 0.0) return a + (b - a) * ((distance_m - along) / len);
    along += len;
  }
  return path.points_m.back();
}

Eigen::Vector2d follow_path(const SteeringAgent& a, const Path& path, double lookahead_s, bool arrive_at_end,
                            double slowing_m) {
  if (path.points_m.empty()) return Eigen::Vector2d::Zero();
  const double total = path_length_m(path);
  const Eigen::Vector2d future = a.position_m + a.velocity_m_s * lookahead_s;
  const double s = path_distance_m(path, future);
  if (arrive_at_end && total - path_distance_m(path, a.position_m) < slowing_m)
    return arrive(a, path.points_m.back(), slowing_m);
  // Seek a point ahead along the path: the agent keeps moving along it,
  // and comes back to it when its prediction leaves the corridor.
  const double ahead = std::max(a.max_speed_m_s * lookahead_s, 0.5);
  const Eigen::Vector2d on_path = path_point_m(path, s);
  if ((future - on_path).norm() > path.radius_m || a.velocity_m_s.norm() < 0.5 * a.max_speed_m_s)
    return seek(a, path_point_m(path, std::min(s + ahead, total)));
  return Eigen::Vector2d::Zero();
}

void integrate(SteeringAgent& a, const Eigen::Vector2d& force_N, double dt_s) {
  const Eigen::Vector2d acceleration = truncate(force_N, a.max_force_N) / a.mass_kg;
  a.velocity_m_s = truncate(a.velocity_m_s + acceleration * dt_s, a.max_speed_m_s);
  a.position_m += a.velocity_m_s * dt_s;
}

}  // namespace skidsim::engine
