// A granular automaton fixed to a moving body (thesis 6.1-6.2,
// docs/material.md): a bucket, a truck bed, a hopper. Its base is the
// body's inner surface, its frame moves with the body, and its slopes are the
// world slopes between surface points, so material slides when the body
// tilts and spills over the rim.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <vector>

#include "terrain/granular_grid.h"

namespace skidsim::terrain {

// The inside of an open container, as a height field over its floor, in the
// container's frame: x from the back wall to the front, y across, z up from
// the floor; the frame's origin is the floor's back corner at y = 0. The
// outermost ring of cells is the walls (their base is the wall's top); all
// four grid edges are open, so material heaped over a wall runs off there.
struct ContainerShape {
  double length_m = 0.87;  // back wall to front, walls included (x)
  double width_m = 1.70;   // side wall to side wall, walls included (y)
  double back_height_m = 0.495;  // the back wall's top above the floor
  // Side walls' top above the floor at the back and at the front; linear in
  // between (a bucket's side plates follow its struck line).
  double side_height_back_m = 0.495;
  double side_height_front_m = 0.05;
  // The front wall's top: 0 for a bucket (its cutting edge is the floor's
  // front), the tailgate for a truck bed.
  double front_height_m = 0.0;
  // The curved heel joining floor and back wall (0: a square corner).
  double heel_radius_m = 0.35;
};

// Throws std::invalid_argument naming the field for a shape that makes no
// container at `cell_size_m` (fewer than 3 x 3 cells, negative heights, ...).
void validate(const ContainerShape& shape, double cell_size_m);

class BodyAutomaton {
 public:
  // The grid has round(length / d) x round(width / d) cells of `cell_size_m`
  // (the scene's cell size: exchanges between automata are exact only
  // between equal cells). It captures what crosses its edges for the
  // exchange (terrain/material_exchange.h).
  BodyAutomaton(const ContainerShape& shape, const SoilFlowParameters& soil, double cell_size_m, double step_dt_s);

  GranularGrid& grid() { return *grid_; }
  const GranularGrid& grid() const { return *grid_; }
  const ContainerShape& shape() const { return shape_; }

  // The container frame in the world (R and A of 6.1) and the body's
  // velocity at the frame's origin. Sets the grid's world up, so the next
  // sweep sees the new tilt.
  void set_pose(const Eigen::Isometry3d& world_from_container, const Eigen::Vector3d& origin_velocity_m_s,
                const Eigen::Vector3d& angular_velocity_rad_s);
  // The body's frame accelerates at `a` (world, m/s^2; the acceleration of
  // the frame's origin, the rotation's centripetal part included): the
  // material feels the apparent gravity g - a of its accelerating frame, so
  // the grid's up tilts towards g z + a. Zero (the default): gravity alone.
  // Takes effect at the next set_pose (the frame's new pose and its
  // acceleration come together), and is kept for every later one.
  void set_frame_acceleration(const Eigen::Vector3d& a_world_m_s2);
  const Eigen::Vector3d& frame_acceleration() const { return frame_acceleration_; }
  // The world's up in the container frame (the floor's tilt), whatever the
  // apparent gravity: what falls, falls along it.
  const Eigen::Vector3d& geometric_up() const { return geometric_up_; }
  const Eigen::Isometry3d& pose() const { return pose_; }
  const Eigen::Isometry3d& inverse_pose() const { return inverse_pose_; }
  // (6.1): p = R + A p', with p' = (x of cell i, y of cell j, height above
  // the floor). Fractional indices are allowed (a cell's face is at +-0.5).
  Eigen::Vector3d world_point(double i, double j, double height_m) const;
  Eigen::Vector3d velocity_at(const Eigen::Vector3d& world_point_m) const;
  // The cell whose column the vertical line through a world point meets
  // (where the line crosses the floor's plane); false outside the grid or
  // when the floor is too steep to be met from above (tilted past ~85 deg).
  bool cell_under(const Eigen::Vector3d& world_point_m, int* i, int* j) const;
  // World height of cell (i, j)'s surface and of its base.
  double surface_world_z(int i, int j) const { return world_point(i, j, grid_->surface_m(i, j)).z(); }

  double material_mass_kg() const;

 private:
  ContainerShape shape_;
  std::unique_ptr<GranularGrid> grid_;
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d inverse_pose_ = Eigen::Isometry3d::Identity();  // world to container
  Eigen::Vector3d origin_velocity_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d frame_acceleration_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d geometric_up_ = Eigen::Vector3d::UnitZ();
  void apply_up();
};

}  // namespace skidsim::terrain
