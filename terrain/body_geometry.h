// What the terrain needs to know about a body's shape and motion to build its
// contact map (thesis 5.2): vertical segment tests against the body's real
// collision shape. The caller provides the shape: the engine backs it with
// Bullet's ray tests, tests with the analytic shapes of body_shapes.h.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace skidsim::terrain {

// The lowest point of a body on a vertical segment, and the body's outward
// face normal there (world frame).
struct VerticalHit {
  double z_m = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};

// The contact map samples a body at the grid's cell corners: a body must be
// at least a cell thick to be seen everywhere (a 2 cm plate edge in 5 cm
// cells slips between corners). Thin tools (the bucket's cutting edge) are
// for the bucket-filling model, which slices instead of pressing (6.4).
class BodyGeometry {
 public:
  virtual ~BodyGeometry() = default;
  // World-frame axis-aligned bounds of the collision shape.
  virtual Eigen::AlignedBox3d world_bounds() const = 0;
  // Lowest point of the body on the segment x = x_m, y = y_m,
  // z_low_m <= z <= z_high_m (a ray cast upward from z_low_m: its first
  // hit, or z_low_m itself when that point is inside the body). False when
  // the segment misses the body.
  virtual bool lowest_hit(double x_m, double y_m, double z_low_m, double z_high_m, VerticalHit* hit) const = 0;
};

// Rigid-body velocity field: v(p) = v_ref + omega x (p - ref).
struct BodyMotion {
  Eigen::Vector3d reference_point_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d linear_velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_at(const Eigen::Vector3d& point_m) const {
    return linear_velocity_m_s + angular_velocity_rad_s.cross(point_m - reference_point_m);
  }
};

}  // namespace skidsim::terrain
