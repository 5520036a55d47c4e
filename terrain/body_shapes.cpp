#include "terrain/body_shapes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace skidsim::terrain {
namespace {

// Clips the line's parameter interval [t_in, t_out] to the slab |a + t u| <= h
// (one coordinate of a line p(t) = a + t u). Returns false when the line
// misses the slab; sets `entered` when the slab's lower bound became t_in.
bool clip_to_slab(double a, double u, double h, double& t_in, double& t_out, bool& entered) {
  entered = false;
  if (std::abs(u) < 1e-12) return std::abs(a) <= h;
  double t0 = (-h - a) / u, t1 = (h - a) / u;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 > t_in) {
    t_in = t0;
    entered = true;
  }
  t_out = std::min(t_out, t1);
  return true;
}

}  // namespace

Eigen::AlignedBox3d OrientedBox::world_bounds() const {
  const Eigen::Matrix3d& r = rotation();
  const Eigen::Vector3d reach = r.cwiseAbs() * half_extents_m;
  return {centre_m - reach, centre_m + reach};
}

bool OrientedBox::lowest_hit(double x_m, double y_m, double z_low_m, double z_high_m, VerticalHit* hit) const {
  // Slab test of the vertical line p(t) = (x, y, t) in the box frame:
  // p_box(t) = a + t u.
  // Written out: called for every corner of every contact map.
  const Eigen::Matrix3d& r = rotation();
  const double px = x_m - centre_m.x(), py = y_m - centre_m.y(), pz = -centre_m.z();
  const Eigen::Vector3d a(r(0, 0) * px + r(1, 0) * py + r(2, 0) * pz, r(0, 1) * px + r(1, 1) * py + r(2, 1) * pz,
                          r(0, 2) * px + r(1, 2) * py + r(2, 2) * pz);
  const Eigen::Vector3d u(r(2, 0), r(2, 1), r(2, 2));
  double t_in = -std::numeric_limits<double>::infinity(), t_out = std::numeric_limits<double>::infinity();
  int entry_axis = 2;
  for (int k = 0; k < 3; ++k) {
    bool entered = false;
    if (!clip_to_slab(a[k], u[k], half_extents_m[k], t_in, t_out, entered)) return false;
    if (entered) entry_axis = k;
  }
  const double lo = std::max(t_in, z_low_m), hi = std::min(t_out, z_high_m);
  if (lo > hi) return false;
  hit->z_m = lo;
  // Entering from below through the face of the entry axis: its outward
  // normal points against the ray.
  Eigen::Vector3d n_box = Eigen::Vector3d::Zero();
  n_box[entry_axis] = u[entry_axis] > 0.0 ? -1.0 : 1.0;
  hit->normal = r * n_box;
  return true;
}

Eigen::AlignedBox3d Sphere::world_bounds() const {
  return {centre_m - Eigen::Vector3d::Constant(radius_m), centre_m + Eigen::Vector3d::Constant(radius_m)};
}

bool Sphere::lowest_hit(double x_m, double y_m, double z_low_m, double z_high_m, VerticalHit* hit) const {
  const double dx = x_m - centre_m.x(), dy = y_m - centre_m.y();
  const double r2 = radius_m * radius_m - dx * dx - dy * dy;
  if (r2 < 0.0) return false;
  const double half = std::sqrt(r2);
  const double lo = std::max(centre_m.z() - half, z_low_m), hi = std::min(centre_m.z() + half, z_high_m);
  if (lo > hi) return false;
  hit->z_m = lo;
  hit->normal = (Eigen::Vector3d(x_m, y_m, lo) - centre_m) / radius_m;
  return true;
}

Eigen::AlignedBox3d Cylinder::world_bounds() const {
  const Eigen::Matrix3d& r = rotation_.of(orientation);
  // Reach along world axis k: the disc's radius times the sine of the angle
  // between the axle and the axis, plus the half width along the axle.
  Eigen::Vector3d reach;
  for (int k = 0; k < 3; ++k) {
    const double along_axle = std::abs(r(k, 1));
    reach[k] = radius_m * std::sqrt(std::max(0.0, 1.0 - along_axle * along_axle)) + half_width_m * along_axle;
  }
  Eigen::AlignedBox3d full(centre_m - reach, centre_m + reach);
  if (!(clip_above_m < full.max().z())) return full;
  // The part of each end disc below the clip height is a circular segment:
  // in the disc's plane, "down" is the steepest way down, "across" is level.
  const Eigen::Vector3d axle = r.col(1);
  Eigen::Vector3d across = axle.cross(Eigen::Vector3d::UnitZ());
  if (across.norm() < 0.3) return full;  // a wheel lying on its side: keep it simple
  across.normalize();
  const Eigen::Vector3d down = axle.cross(across).normalized() * (axle.cross(across).z() < 0.0 ? 1.0 : -1.0);
  // The lower end disc: the distance along `down` from its centre to where
  // the clip plane cuts it. Its part below the clip is the larger; one
  // in-plane rectangle holding it, placed at both ends, bounds every
  // segment between the discs.
  const double s_low = (centre_m.z() - half_width_m * std::abs(axle.z()) - clip_above_m) / -down.z();
  Eigen::AlignedBox3d clipped;
  if (s_low >= radius_m) {  // nothing below the clip: just the lowest point
    clipped.extend(Eigen::Vector3d(centre_m - half_width_m * std::copysign(1.0, axle.z()) * axle + radius_m * down));
    return clipped;
  }
  const double from = std::max(s_low, -radius_m);
  const double half_chord = s_low > 0.0 ? std::sqrt(radius_m * radius_m - s_low * s_low) : radius_m;
  for (double side : {-half_width_m, half_width_m})
    for (double along_down : {from, radius_m})
      for (double a : {-half_chord, half_chord})
        clipped.extend(Eigen::Vector3d(centre_m + side * axle + along_down * down + a * across));
  return clipped.intersection(full);
}

bool Cylinder::lowest_hit(double x_m, double y_m, double z_low_m, double z_high_m, VerticalHit* hit) const {
  // The vertical line in the cylinder's frame: p(t) = a + t u, the axle
  // along y. Inside: p_x^2 + p_z^2 <= R^2 and |p_y| <= h.
  const Eigen::Matrix3d& r = rotation_.of(orientation);
  const Eigen::Vector3d a = r.transpose() * (Eigen::Vector3d(x_m, y_m, 0.0) - centre_m);
  const Eigen::Vector3d u = r.transpose().col(2);
  double t_in = -std::numeric_limits<double>::infinity(), t_out = std::numeric_limits<double>::infinity();
  bool through_cap = false;
  // The disc: quadratic in t.
  const double qa = u.x() * u.x() + u.z() * u.z();
  const double qb = 2.0 * (a.x() * u.x() + a.z() * u.z());
  const double qc = a.x() * a.x() + a.z() * a.z() - radius_m * radius_m;
  if (qa < 1e-12) {
    if (qc > 0.0) return false;  // a line along the axle, outside the disc
  } else {
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc < 0.0) return false;
    const double root = std::sqrt(disc);
    t_in = (-qb - root) / (2.0 * qa);
    t_out = (-qb + root) / (2.0 * qa);
  }
  // The two end caps: a slab along the axle.
  if (!clip_to_slab(a.y(), u.y(), half_width_m, t_in, t_out, through_cap)) return false;
  const double lo = std::max(t_in, z_low_m), hi = std::min(t_out, z_high_m);
  if (lo > hi) return false;
  hit->z_m = lo;
  const Eigen::Vector3d p = a + t_in * u;
  const Eigen::Vector3d n_local =
      through_cap ? Eigen::Vector3d(0.0, u.y() > 0.0 ? -1.0 : 1.0, 0.0) : Eigen::Vector3d(p.x(), 0.0, p.z()) / radius_m;
  hit->normal = r * n_local;
  return true;
}

void TriangleMesh::update() {
  world_.resize(vertices_body_m.size());
  bounds_.setEmpty();
  for (std::size_t k = 0; k < vertices_body_m.size(); ++k) {
    world_[k] = pose * vertices_body_m[k];
    bounds_.extend(world_[k]);
  }
  footprints_.resize(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    Eigen::AlignedBox2d b;
    for (int k = 0; k < 3; ++k) b.extend(world_[triangles[t][k]].head<2>());
    footprints_[t] = b;
  }
}

bool TriangleMesh::lowest_hit(double x_m, double y_m, double z_low_m, double z_high_m, VerticalHit* hit) const {
  const Eigen::Vector2d q(x_m, y_m);
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_normal = Eigen::Vector3d::UnitZ();
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (!footprints_[t].contains(q)) continue;
    const Eigen::Vector3d& a = world_[triangles[t][0]];
    const Eigen::Vector3d& b = world_[triangles[t][1]];
    const Eigen::Vector3d& c = world_[triangles[t][2]];
    // Barycentric coordinates of q in the triangle's footprint.
    const Eigen::Vector2d e1 = (b - a).head<2>(), e2 = (c - a).head<2>(), w = q - a.head<2>();
    const double det = e1.x() * e2.y() - e1.y() * e2.x();
    if (std::abs(det) < 1e-14) continue;  // a vertical triangle: no vertical line crosses it
    const double s = (w.x() * e2.y() - w.y() * e2.x()) / det, r = (e1.x() * w.y() - e1.y() * w.x()) / det;
    if (s < 0.0 || r < 0.0 || s + r > 1.0) continue;
    const double z = a.z() + s * (b.z() - a.z()) + r * (c.z() - a.z());
    // The first crossing above z_low, wherever it is: if it leaves the body
    // (an upward face), z_low is inside even when the whole segment is.
    if (z < z_low_m || z >= best) continue;
    best = z;
    best_normal = (b - a).cross(c - a).normalized();
  }
  if (!std::isfinite(best)) return false;
  if (best_normal.z() > 0.0) {
    hit->z_m = z_low_m;
  } else if (best <= z_high_m) {
    hit->z_m = best;
  } else {
    return false;
  }
  hit->normal = best_normal;
  return true;
}

TriangleMesh TriangleMesh::box(const Eigen::Vector3d& h) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k)
    m.vertices_body_m.emplace_back((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z());
  // Two counter-clockwise triangles per face, seen from outside.
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    m.triangles.emplace_back(f[0], f[1], f[2]);
    m.triangles.emplace_back(f[0], f[2], f[3]);
  }
  m.update();
  return m;
}

}  // namespace skidsim::terrain
