// Analytic collision shapes behind the BodyGeometry query: an oriented box,
// a sphere and a triangle mesh. Tests and tools use them; the engine uses
// Bullet's shapes through the same interface.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <vector>

#include "terrain/body_geometry.h"

namespace skidsim::terrain {

// The rotation matrix of a shape's quaternion, rebuilt only when the
// quaternion changes (the contact map queries a shape hundreds of times a step).
class RotationCache {
 public:
  const Eigen::Matrix3d& of(const Eigen::Quaterniond& q) const {
    if (q.coeffs() != quaternion_) {
      matrix_ = q.toRotationMatrix();
      quaternion_ = q.coeffs();
    }
    return matrix_;
  }

 private:
  mutable Eigen::Matrix3d matrix_ = Eigen::Matrix3d::Identity();
  mutable Eigen::Vector4d quaternion_ = Eigen::Vector4d(0.0, 0.0, 0.0, 1.0);
};

// A box of half extents `half_extents_m` centred at `centre_m`, rotated by
// `orientation` (body to world).
struct OrientedBox final : BodyGeometry {
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d half_extents_m = Eigen::Vector3d::Constant(0.5);

  Eigen::AlignedBox3d world_bounds() const override;
  bool lowest_hit(double x_m, double y_m, double z_low_m, double z_high_m, VerticalHit* hit) const override;

 private:
  const Eigen::Matrix3d& rotation() const { return rotation_.of(orientation); }
  RotationCache rotation_;
};

struct Sphere final : BodyGeometry {
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();
  double radius_m = 0.5;

  Eigen::AlignedBox3d world_bounds() const override;
  bool lowest_hit(double x_m, double y_m, double z_low_m, double z_high_m, VerticalHit* hit) const override;
};

// A solid cylinder (a wheel): radius `radius_m`, its axis along the body's y
// (the axle), `half_width_m` either side of the centre.
struct Cylinder final : BodyGeometry {
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  double radius_m = 0.3;
  double half_width_m = 0.15;
  // Only the part below this height matters (the highest soil under the
  // wheel): world_bounds then covers just that part, so a wheel sunk a few
  // centimetres maps the cells of its patch, not its whole side view.
  double clip_above_m = std::numeric_limits<double>::infinity();

  Eigen::AlignedBox3d world_bounds() const override;
  bool lowest_hit(double x_m, double y_m, double z_low_m, double z_high_m, VerticalHit* hit) const override;

 private:
  RotationCache rotation_;
};

// A closed triangle mesh with outward (counter-clockwise) winding, placed by
// a rigid transform. Brute force over the triangles whose footprint holds
// the query point: meant for tool meshes of tens to hundreds of triangles.
struct TriangleMesh final : BodyGeometry {
  std::vector<Eigen::Vector3d> vertices_body_m;
  std::vector<Eigen::Vector3i> triangles;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // body to world

  // Caches world vertices and per-triangle bounds; call after changing the
  // pose or the mesh.
  void update();
  Eigen::AlignedBox3d world_bounds() const override { return bounds_; }
  bool lowest_hit(double x_m, double y_m, double z_low_m, double z_high_m, VerticalHit* hit) const override;

  // A box as 12 triangles (for tests that compare mesh and box).
  static TriangleMesh box(const Eigen::Vector3d& half_extents_m);

 private:
  std::vector<Eigen::Vector3d> world_;
  std::vector<Eigen::AlignedBox2d> footprints_;
  Eigen::AlignedBox3d bounds_;
};

}  // namespace skidsim::terrain
