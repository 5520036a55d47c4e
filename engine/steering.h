// Steering behaviours (Reynolds; seed 004, ch. 2): a character is a point
// mass with a top speed and a largest steering force; each behaviour
// returns the force it asks for (newtons: the mass times the change of
// velocity it wants, over kSteeringResponseS), the caller sums them
// (weighted), and integrate() truncates the sum to the largest force and
// the speed to the top speed. On the ground plane (x, y), SI units. Plain
// structs and free functions, deterministic, no allocation.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace skidsim::engine {

// How quickly a character wants to reach the velocity a behaviour asks for.
inline constexpr double kSteeringResponseS = 0.25;

struct SteeringAgent {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity_m_s = Eigen::Vector2d::Zero();
  double mass_kg = 80.0;
  double max_speed_m_s = 1.4;  // a walk
  double max_force_N = 200.0;
  double radius_m = 0.3;       // for separation and contact
};

// v truncated to length `max` (unchanged if shorter).
Eigen::Vector2d truncate(const Eigen::Vector2d& v, double max);

// Towards the target at top speed: desired velocity minus velocity.
Eigen::Vector2d seek(const SteeringAgent& a, const Eigen::Vector2d& target_m);
// Away from it, within `panic_m` (beyond it: nothing).
Eigen::Vector2d flee(const SteeringAgent& a, const Eigen::Vector2d& threat_m, double panic_m);
// Seek that slows down inside `slowing_m`: the desired speed falls in
// proportion to the distance (seed 004: ramped speed = max speed x
// distance / slowing distance), clipped to what the largest force can
// still stop, so the agent stops at the target instead of overshooting.
Eigen::Vector2d arrive(const SteeringAgent& a, const Eigen::Vector2d& target_m, double slowing_m);
// Seek / flee the point a moving target will reach in the time it takes to
// cover the distance at top speed.
Eigen::Vector2d pursue(const SteeringAgent& a, const Eigen::Vector2d& target_m, const Eigen::Vector2d& target_velocity_m_s);
Eigen::Vector2d evade(const SteeringAgent& a, const Eigen::Vector2d& threat_m, const Eigen::Vector2d& threat_velocity_m_s,
                      double panic_m);
// Away from neighbours within `neighbourhood_m`: each pushes along the line
// between them, weighted by the inverse of the gap (seed 004: normalised
// offset over distance), scaled to at most the largest force.
Eigen::Vector2d separation(const SteeringAgent& a, const std::vector<SteeringAgent>& others, double neighbourhood_m);
// Towards the neighbours' centre; along their mean velocity.
Eigen::Vector2d cohesion(const SteeringAgent& a, const std::vector<SteeringAgent>& others, double neighbourhood_m);
Eigen::Vector2d alignment(const SteeringAgent& a, const std::vector<SteeringAgent>& others, double neighbourhood_m);

// A polyline to walk along, within `radius_m` of it.
struct Path {
  std::vector<Eigen::Vector2d> points_m;
  double radius_m = 0.5;
};
// Where along the path (its arc length) a point is closest.
double path_distance_m(const Path& path, const Eigen::Vector2d& p);
Eigen::Vector2d path_point_m(const Path& path, double distance_m);
double path_length_m(const Path& path);
// Path following: predict where the agent will be in `lookahead_s`; if that
// is off the path (farther than its radius), seek the path point a little
// beyond the prediction's projection; else nothing. Near the path's end
// (`arrive_at_end`), arrive at the last point instead.
Eigen::Vector2d follow_path(const SteeringAgent& a, const Path& path, double lookahead_s, bool arrive_at_end,
                            double slowing_m);

// One step: acceleration = truncate(force, max force) / mass; the new
// velocity truncated to the top speed; position moved by it.
void integrate(SteeringAgent& a, const Eigen::Vector2d& force_N, double dt_s);

}  // namespace skidsim::engine
