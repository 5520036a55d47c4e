// The apparent gravity of a container's accelerating frame (a bucket, a
// truck's bed): its origin's acceleration, from the change of the velocity
// it is posed with each step, low-pass filtered; the container's automaton
// then lets its load feel g - a (terrain::BodyAutomaton::set_frame_acceleration).
#pragma once

#include <Eigen/Core>

namespace skidsim::engine {

// The load feels its frame's acceleration through a first-order low-pass of
// this time constant: about the time a layer of the load takes to start
// sliding, sqrt(h / g) for h ~ 0.1 m, long against the 2 ms step's contact
// chatter of tyres and arm, which unfiltered would rock the load and, through
// its load point, the machine.
constexpr double kFrameAccelerationFilterS = 0.1;

struct FrameAcceleration {
  bool known = false;  // a velocity has been seen
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d filtered_m_s2 = Eigen::Vector3d::Zero();
};

// Feeds the frame origin's velocity at this step (step_s after the last);
// returns the filtered acceleration (zero until two velocities are seen).
inline const Eigen::Vector3d& update_frame_acceleration(FrameAcceleration& f, const Eigen::Vector3d& v_m_s, double step_s) {
  if (f.known) {
    const Eigen::Vector3d raw = (v_m_s - f.velocity_m_s) / step_s;
    f.filtered_m_s2 += (raw - f.filtered_m_s2) * (step_s / (kFrameAccelerationFilterS + step_s));
  }
  f.velocity_m_s = v_m_s;
  f.known = true;
  return f.filtered_m_s2;
}

}  // namespace skidsim::engine
