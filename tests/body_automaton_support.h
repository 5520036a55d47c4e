// Helpers for the tests of automata on moving bodies: a container posed by
// its pitch about its front edge, and a scene stepped the way the engine
// steps it (grids, then the exchange).
#pragma once

#include <Eigen/Geometry>

#include <cmath>

#include "terrain/body_automaton.h"
#include "terrain/material_exchange.h"

namespace skidsim::terrain::testing {

// The container's frame with its front edge's centre at `front_centre_m`,
// pitched by `pitch_rad` about the world y axis (> 0 lowers the front: a
// bucket dumping), and the frame's velocity when the pitch changes at
// `pitch_rate_rad_s` about that edge.
inline void pose_about_front(BodyAutomaton& a, const Eigen::Vector3d& front_centre_m, double pitch_rad,
                             double pitch_rate_rad_s = 0.0, const Eigen::Vector3d& travel_m_s = Eigen::Vector3d::Zero()) {
  const ContainerShape& s = a.shape();
  const double d = a.grid().cell_size_m();
  const Eigen::Vector3d front_local(a.grid().nx() * d, 0.5 * a.grid().ny() * d, 0.0);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pose.translation() = front_centre_m - pose.linear() * front_local;
  const Eigen::Vector3d omega(0.0, pitch_rate_rad_s, 0.0);
  (void)s;
  a.set_pose(pose, travel_m_s + omega.cross(pose.translation() - front_centre_m), omega);
}

// Fills a container's inside (walls excluded) to `level_m` above its floor
// where the base is lower.
inline void fill_to(BodyAutomaton& a, double level_m) {
  GranularGrid& g = a.grid();
  for (int j = 1; j + 1 < g.ny(); ++j)
    for (int i = 1; i + 1 < g.nx(); ++i) g.set_material_m(i, j, std::max(0.0, level_m - g.base_m(i, j)));
}

}  // namespace skidsim::terrain::testing
