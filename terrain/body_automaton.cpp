#include "terrain/body_automaton.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace skidsim::terrain {
namespace {

[[noreturn]] void bad_shape(const char* field, double value, const char* expected) {
  std::ostringstream msg;
  msg << "container shape: " << field << " = " << value << " (expected " << expected << ")";
  throw std::invalid_argument(msg.str());
}

int cells_along(double length_m, double cell_size_m) {
  return static_cast<int>(std::lround(std::min(length_m / cell_size_m, 1e6)));
}

}  // namespace

void validate(const ContainerShape& s, double cell_size_m) {
  if (!(cell_size_m > 0.0 && std::isfinite(cell_size_m))) bad_shape("cell_size_m", cell_size_m, "> 0");
  if (!(s.length_m < 100.0 && cells_along(s.length_m, cell_size_m) >= 3))
    bad_shape("length_m", s.length_m, "at least 3 cells, under 100 m");
  if (!(s.width_m < 100.0 && cells_along(s.width_m, cell_size_m) >= 3))
    bad_shape("width_m", s.width_m, "at least 3 cells, under 100 m");
  const struct {
    const char* name;
    double value;
  } heights[] = {{"back_height_m", s.back_height_m},
                 {"side_height_back_m", s.side_height_back_m},
                 {"side_height_front_m", s.side_height_front_m},
                 {"front_height_m", s.front_height_m},
                 {"heel_radius_m", s.heel_radius_m}};
  for (const auto& h : heights)
    if (!(h.value >= 0.0 && h.value < 100.0)) bad_shape(h.name, h.value, "in [0, 100) m");
  if (s.heel_radius_m > s.back_height_m) bad_shape("heel_radius_m", s.heel_radius_m, "<= back_height_m");
}

BodyAutomaton::BodyAutomaton(const ContainerShape& shape, const SoilFlowParameters& soil, double cell_size_m,
                             double step_dt_s)
    : shape_(shape) {
  validate(shape, cell_size_m);
  GridSpec spec;
  spec.nx = cells_along(shape.length_m, cell_size_m);
  spec.ny = cells_along(shape.width_m, cell_size_m);
  spec.cell_size_m = cell_size_m;
  spec.origin_m = Eigen::Vector2d::Constant(0.5 * cell_size_m);
  spec.edges = {EdgeKind::kOpen, EdgeKind::kOpen, EdgeKind::kOpen, EdgeKind::kOpen};
  spec.flow_bound_fraction = 0.5;  // see GridSpec: the grid tilts
  // A body's grid is small: it may take more sub-steps than a site's.
  grid_ = std::make_unique<GranularGrid>(spec, soil, step_dt_s, 256);
  grid_->capture_edge_outflow(true);
  const double d = cell_size_m;
  const double inner_length = (spec.nx - 1) * d;  // back wall's inner face to the front
  for (int j = 0; j < spec.ny; ++j) {
    for (int i = 0; i < spec.nx; ++i) {
      const double x = (i + 0.5) * d;
      double base = 0.0;
      // The heel: a quarter circle from the floor up the back wall, sampled
      // at the cell centre's distance from the wall's inner face.
      const double from_back = x - d;
      if (shape.heel_radius_m > 0.0 && from_back < shape.heel_radius_m) {
        const double r = shape.heel_radius_m, u = r - std::max(0.0, from_back);
        base = r - std::sqrt(std::max(0.0, r * r - u * u));
      }
      if (i == 0) base = shape.back_height_m;
      if (i == spec.nx - 1 && spec.nx > 1) base = std::max(base, shape.front_height_m);
      if (j == 0 || j == spec.ny - 1) {
        const double t = std::clamp(from_back / inner_length, 0.0, 1.0);
        base = std::max(base, (1.0 - t) * shape.side_height_back_m + t * shape.side_height_front_m);
      }
      grid_->set_base_m(i, j, base);
    }
  }
}

void BodyAutomaton::set_pose(const Eigen::Isometry3d& world_from_container, const Eigen::Vector3d& origin_velocity_m_s,
                             const Eigen::Vector3d& angular_velocity_rad_s) {
  pose_ = world_from_container;
  inverse_pose_ = pose_.inverse(Eigen::Isometry);
  origin_velocity_ = origin_velocity_m_s;
  angular_velocity_ = angular_velocity_rad_s;
  apply_up();
}

void BodyAutomaton::set_frame_acceleration(const Eigen::Vector3d& a_world_m_s2) {
  if (!a_world_m_s2.allFinite()) throw std::invalid_argument("set_frame_acceleration: the acceleration must be finite");
  frame_acceleration_ = a_world_m_s2;
}

void BodyAutomaton::apply_up() {
  // Normalised as GranularGrid::set_world_up normalises its up, so that
  // without an apparent gravity the two are the same numbers.
  const Eigen::Vector3d up_geometric = pose_.linear().transpose() * Eigen::Vector3d::UnitZ();
  geometric_up_ = up_geometric / up_geometric.norm();
  if (frame_acceleration_.isZero(0.0)) {
    grid_->set_world_up(geometric_up_);
    return;
  }
  // Apparent gravity g - a (Newton in the accelerating frame): up along
  // g z + a. A frame falling faster than a tenth of g keeps a tenth of g's
  // up (the material is then airborne more than it slides).
  Eigen::Vector3d up = kGravity_m_s2 * Eigen::Vector3d::UnitZ() + frame_acceleration_;
  up.z() = std::max(up.z(), 0.1 * kGravity_m_s2);
  grid_->set_world_up(pose_.linear().transpose() * up);
}

Eigen::Vector3d BodyAutomaton::world_point(double i, double j, double height_m) const {
  const double d = grid_->cell_size_m();
  return pose_ * Eigen::Vector3d((i + 0.5) * d, (j + 0.5) * d, height_m);
}

Eigen::Vector3d BodyAutomaton::velocity_at(const Eigen::Vector3d& world_point_m) const {
  return origin_velocity_ + angular_velocity_.cross(world_point_m - pose_.translation());
}

bool BodyAutomaton::cell_under(const Eigen::Vector3d& world_point_m, int* i, int* j) const {
  const Eigen::Vector3d& up = geometric_up_;
  if (up.z() < 0.087) return false;  // the floor faces sideways or down
  const Eigen::Vector3d p = inverse_pose_ * world_point_m;
  const Eigen::Vector3d on_floor = p - (p.z() / up.z()) * up;
  const double d = grid_->cell_size_m();
  const double fi = std::floor(on_floor.x() / d), fj = std::floor(on_floor.y() / d);
  if (!(fi >= 0.0 && fj >= 0.0 && fi < grid_->nx() && fj < grid_->ny())) return false;
  *i = static_cast<int>(fi);
  *j = static_cast<int>(fj);
  return true;
}

double BodyAutomaton::material_mass_kg() const {
  return static_cast<double>(grid_->total_quanta()) * grid_->quantum_mass_kg();
}

}  // namespace skidsim::terrain
