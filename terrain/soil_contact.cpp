#include "terrain/soil_contact.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <stdexcept>

namespace skidsim::terrain {
namespace {

constexpr double kFullyCovered = 1.0 - 1e-9;
constexpr double kPressOnlyCovering = 0.05;  // a wheel's cells it covers by at least this much
constexpr int kMaxBodyId = 65535;

// Speed of a point along face direction f (+x, -x, +y, -y).
double along(const Eigen::Vector3d& v, int f) {
  return f == 0 ? v.x() : f == 1 ? -v.x() : f == 2 ? v.y() : -v.y();
}

// Integral over u in [u0, u1] of max(0, a - t u), t > 0: the section of soil
// above a plane rising at slope t, for a surface a above the plane's foot.
double clipped_section(double a, double t, double u0, double u1) {
  if (a <= t * u0) return 0.0;
  const double hi = std::min(u1, a / t);
  return a * (hi - u0) - 0.5 * t * (hi * hi - u0 * u0);
}

}  // namespace

SoilContactModel::SoilContactModel(GranularGrid& grid, const SoilMechanics& soil) : grid_(grid) { add_soil(soil); }

int SoilContactModel::add_soil(const SoilMechanics& soil) {
  validate(soil);
  if (regions_.size() >= 256) throw std::invalid_argument("SoilContactModel::add_soil: at most 256 soils");
  SoilRegion r;
  r.soil = soil;
  r.phi_rad = deg_to_rad(soil.friction_angle_deg);
  r.tan_tool_friction = std::tan(deg_to_rad(soil.tool_friction_angle_deg));
  r.rho_table = WedgeAngleTable(r.phi_rad);
  // The wedge's soil weighs as the grid's (wedge_reactions' gamma g).
  r.cutting = cutting_soil(soil, grid_.soil().bulk_density_kg_m3);
  regions_.push_back(r);
  return static_cast<int>(regions_.size()) - 1;
}

void SoilContactModel::set_soil_region(int i, int j, int soil_index) {
  if (!grid_.contains(i, j) || soil_index < 0 || soil_index >= static_cast<int>(regions_.size()))
    throw std::invalid_argument("SoilContactModel::set_soil_region: cell outside the grid or unknown soil index");
  if (region_of_cell_.empty()) region_of_cell_.assign(static_cast<std::size_t>(grid_.nx()) * grid_.ny(), 0);
  region_of_cell_[grid_.index(i, j)] = static_cast<std::uint8_t>(soil_index);
}

void SoilContactModel::reserve_body(int body_id, double diagonal_m) {
  // Whatever its orientation, a body covers at most a square of its diagonal.
  BodyState& state = body_state(body_id);
  const double reach = diagonal_m / grid_.cell_size_m() + 2.0;
  const std::size_t cells =
      static_cast<std::size_t>(std::min(reach * reach, static_cast<double>(grid_.nx()) * grid_.ny()));
  state.covered.reserve(cells);
  state.covered_next.reserve(cells);
  state.map.cells.reserve(cells);
  state.next.cells.reserve(cells);
  state.sliced.reserve(cells);
  slots_.reserve(std::max(slots_.capacity(), cells));
  // A fracture wedge walks at most across the grid.
  const std::size_t across = static_cast<std::size_t>(std::max(grid_.nx(), grid_.ny())) + 2;
  wedge_cells_.reserve(across);
  wedge_area_.reserve(across);
  mapper_.reserve(static_cast<std::size_t>((reach + 1.0) * (reach + 1.0)));
}

void SoilContactModel::set_tool_face(int body_id, const Eigen::Vector3d& outward_normal_world) {
  BodyState& state = body_state(body_id);
  state.has_tool_face = outward_normal_world.allFinite() && outward_normal_world.norm() > 0.0;
  if (state.has_tool_face) state.tool_face_normal = outward_normal_world.normalized();
}

void SoilContactModel::set_press_only(int body_id, bool on) { body_state(body_id).press_only = on; }

bool SoilContactModel::in_contact_map(int body_id, std::uint32_t cell) const {
  if (body_id < 0 || body_id >= static_cast<int>(bodies_.size()) || !bodies_[body_id].in_contact) return false;
  const std::vector<CellContact>& cells = bodies_[body_id].map.cells;
  const auto it = std::lower_bound(cells.begin(), cells.end(), cell,
                                   [](const CellContact& c, std::uint32_t v) { return c.cell < v; });
  return it != cells.end() && it->cell == cell;
}

double SoilContactModel::tool_rake_rad(const BodyState& state, int f) const {
  // The face's angle from the horizontal seen along direction f: its normal
  // leans ahead by atan2(n . D, n_z) from the vertical. McKyes-Ali's
  // mechanism holds from a shallow rake to a vertical face; a face that does
  // not face f (its horizontal normal more than ~73 deg from it, as for the
  // faces a cutting edge meets: edge-on or turned away, it pushes nothing
  // that way), an overhanging one, or no declared face pushes with the
  // vertical interface.
  constexpr double kShallowestRake_rad = deg_to_rad(10.0);
  constexpr double kVertical_rad = 0.5 * kPi;
  if (!state.has_tool_face) return kVertical_rad;
  const Eigen::Vector3d& n = state.tool_face_normal;
  const double ahead = n.x() * kFaceStep[f][0] + n.y() * kFaceStep[f][1];
  if (!face_ahead(f, n.x(), n.y(), std::hypot(n.x(), n.y())) || !(n.z() > 0.0)) return kVertical_rad;
  return std::clamp(std::atan2(ahead, n.z()), kShallowestRake_rad, kVertical_rad);
}

void SoilContactModel::set_slicing(int body_id, bool on, const Eigen::Vector2d& forward) {
  BodyState& state = body_state(body_id);
  state.slicing = on && forward.norm() > 1e-9;
  if (state.slicing) state.slicing_forward = forward.normalized();
}

void SoilContactModel::release(int body_id) {
  if (body_id < 0 || body_id >= static_cast<int>(bodies_.size())) return;
  BodyState& state = bodies_[body_id];
  for (std::uint32_t c : state.covered) cover(c, false);
  state.covered.clear();
  state.map.clear();
  state.next.clear();
  state.sliced.clear();
  state.in_contact = false;
}

void SoilContactModel::cover(std::uint32_t cell, bool on) {
  // Several bodies may cover one cell: it blocks the avalanches while any
  // of them does.
  if (cover_count_.empty()) cover_count_.assign(static_cast<std::size_t>(grid_.nx()) * grid_.ny(), 0);
  std::uint8_t& count = cover_count_[cell];
  if (on) {
    if (count++ == 0) grid_.set_covered(static_cast<int>(cell), true);
  } else if (count > 0 && --count == 0) {
    grid_.set_covered(static_cast<int>(cell), false);
  }
}

void SoilContactModel::update_covered(BodyState& state) {
  // Cells covered now vs. before; both lists in increasing cell order.
  std::size_t k = 0;
  const std::vector<std::uint32_t>& before = state.covered;
  std::vector<std::uint32_t>& now = state.covered_next;
  now.clear();
  // As much room as the map's storage: grows with it, not as more is covered.
  if (now.capacity() < state.next.cells.capacity()) now.reserve(state.next.cells.capacity());
  // A rolling wheel holds up the rut's walls it touches (the soil it is
  // pressing): its partly covered cells take no avalanche either.
  const double covering = state.press_only ? kPressOnlyCovering : kFullyCovered;
  for (const CellContact& c : state.next.cells)
    if (c.covered_fraction >= covering) now.push_back(c.cell);
  std::size_t n = 0;
  while (k < before.size() || n < now.size()) {
    if (n >= now.size() || (k < before.size() && before[k] < now[n])) {
      cover(before[k++], false);
    } else if (k >= before.size() || now[n] < before[k]) {
      cover(now[n++], true);
    } else {
      ++k;
      ++n;
    }
  }
  state.covered.swap(now);
}

double SoilContactModel::free_surface_m(int cell, double covered_fraction, double covered_level_m) const {
  const double surface = grid_.surface_at(cell);
  if (covered_fraction >= kFullyCovered) return surface;
  return (surface - covered_fraction * covered_level_m) / (1.0 - covered_fraction);
}

double SoilContactModel::plastic_sinkage_under(int cell, double covered_fraction) const {
  // plastic_ is the volume taken from under bodies (a height over the cell)
  // and pressed_ the largest fraction of the cell it was taken from: per
  // unit of pressed area it is plastic_ / pressed_. A body covering more
  // than that area covers unpressed soil too, hence the max.
  return plastic_[cell] / std::max({static_cast<double>(pressed_[cell]), covered_fraction, 1e-9});
}

void SoilContactModel::record_plastic(CellContact& c, std::int64_t quanta) {
  if (quanta <= 0) return;
  const double height = quanta * kHeightQuantumM;
  plastic_[c.cell] += static_cast<float>(height);
  pressed_[c.cell] = std::max(pressed_[c.cell], static_cast<float>(c.covered_fraction));
  if (c.covered_fraction < kFullyCovered) c.covered_level_m -= height / c.covered_fraction;
}

void SoilContactModel::press(CellContact& c, const BodyMotion& motion, BodyReaction& out) {
  const int cell = static_cast<int>(c.cell);
  const SoilRegion& region = region_at(cell);
  const SoilMechanics& soil = region.soil;
  const double modulus_Pa = region.modulus_Pa;
  const double d = grid_.cell_size_m();
  const double area = c.covered_fraction * d * d;
  const bool full = c.covered_fraction >= kFullyCovered;
  const double level = full ? grid_.surface_at(cell) : c.covered_level_m;
  // Sinkage of the covered part from its undisturbed level: the plastic
  // sinkage already realised under it counted back.
  const double realised = plastic_sinkage_under(cell, c.covered_fraction);
  const double sinkage = level + realised - c.bottom_z_m;
  const double peak = peak_[cell];
  const PressureSlope ps = bekker_pressure(soil, modulus_Pa, peak, sinkage);
  double pressure = ps.pressure_Pa;
  double slope = ps.slope_Pa_per_m;
  if (sinkage > peak) {
    // Loading: the plastic part of the new peak stays (5.4.1, d_p into z),
    // z_max - p(z_max) / k_u.
    peak_[cell] = static_cast<float>(sinkage);
    const double plastic = std::max(0.0, sinkage - pressure / unload_stiffness_Pa_per_m(soil, sinkage));
    // The volume (as a height over the cell) to take from under the body.
    const double more = c.covered_fraction * (plastic - realised);
    const auto quanta = more > 0.0 ? static_cast<std::int64_t>(more / kHeightQuantumM) : 0;
    if (quanta > 0 && soil.model == VerticalLoadModel::kBekker) {
      // Compressible: the soil under the body compacts.
      const std::int64_t done = grid_.compact_quanta(cell, quanta);
      out.compacted_m3 += done * grid_.quantum_volume_m3();
      record_plastic(c, done);
    } else if (quanta > 0) {
      // Incompressible (5.3): the same volume leaves from under the load
      // for the contour of the pressed zone, away from the footprint's
      // middle; recorded once it has moved (it cannot where a wall or
      // another body is in the way: the soil is confined).
      const Eigen::Vector2d outward = c.point_m.head<2>() - current_footprint_centre_;
      const int direction = std::abs(outward.x()) >= std::abs(outward.y()) ? (outward.x() >= 0.0 ? 0 : 1)
                                                                           : (outward.y() >= 0.0 ? 2 : 3);
      pushes_.push_back({c.cell, direction, quanta * kHeightQuantumM, true});
    }
  }
  const double sink_rate = -c.velocity_m_s.z();
  double damping = 0.0;
  if (pressure > 0.0) {
    damping = 1000.0 * soil.damping_kPa_s_per_m;
    pressure = std::max(0.0, pressure + damping * sink_rate);
  }
  // A cell the body is leaving faster than the soil springs back carries
  // nothing, and must not report stiffness or damping either: applied
  // implicitly they would pull the body back as if the soil were sticky.
  if (pressure <= 0.0) {
    pressure = 0.0;
    slope = 0.0;
    damping = 0.0;
  }
  const double base_penetration = static_cast<double>(grid_.base_at(cell)) - c.bottom_z_m;
  double base_force = 0.0, base_stiffness = 0.0;
  if (base_penetration > 0.0) {
    base_stiffness = 1000.0 * soil.base_stiffness_kPa_per_m * area;
    base_force = base_stiffness * base_penetration;
    out.base_penetration_m = std::max(out.base_penetration_m, base_penetration);
  }
  const double vertical = pressure * area + base_force;
  // The pressure acts along the body's face normal; its vertical part is the
  // pressure on the projected area (tilt capped so a steep face cannot
  // produce an unbounded side force).
  const double up = std::max(-c.normal.z(), 0.25);
  Eigen::Vector3d force = Eigen::Vector3d(-c.normal.x(), -c.normal.y(), up) * (vertical / up);
  if (-c.normal.z() <= 0.0) force = Eigen::Vector3d(0.0, 0.0, vertical);
  out.force_N += force;
  out.torque_Nm += (c.point_m - motion.reference_point_m).cross(force);
  if (base_force > 0.0) {
    const Eigen::Vector3d base = force * (base_force / vertical);
    out.base_force_N += base;
    out.base_torque_Nm += (c.point_m - motion.reference_point_m).cross(base);
  }
  out.normal_stiffness_N_per_m += slope * area + base_stiffness;
  out.normal_damping_N_s_per_m += damping * area;
  if (vertical <= 0.0) return;
  out.contact_area_m2 += area;
  // Mohr-Coulomb on the soil-tool contact (5.4.2): (a + sigma_n tan delta) A,
  // over the cells whose soil carries load; it acts where its parts do. The
  // hard base's share is not soil: its friction is the base contact's own
  // (an engine's rigid contact).
  if (pressure <= 0.0) return;
  const double shear = 1000.0 * soil.tool_adhesion_kPa * area + pressure * area * region.tan_tool_friction;
  out.shear_bound_N += shear;
  out.shear_point_m += shear * c.point_m;
}

int SoilContactModel::region_in_front(const CellContact& c, int f) const {
  const int i = c.i + kFaceStep[f][0], j = c.j + kFaceStep[f][1];
  return grid_.contains(i, j) ? region_index(grid_.index(i, j)) : region_index(static_cast<int>(c.cell));
}

double SoilContactModel::free_level_cap(int cell, double covered_fraction, int f) const {
  // The free part of a partly covered cell adjoins the cell in front: its
  // soil stands at most a repose slope above that cell's. (Without the cap,
  // soil an avalanche brings into a cell that is almost covered would stand
  // impossibly high on its sliver of free area.)
  const int i = cell % grid_.nx() + kFaceStep[f][0], j = cell / grid_.nx() + kFaceStep[f][1];
  if (!grid_.contains(i, j) || map_slot(i, j) >= 0) return std::numeric_limits<double>::infinity();
  return grid_.surface_at(grid_.index(i, j)) +
         (1.0 - covered_fraction) * grid_.cell_size_m() * grid_.flow_law().tan_repose;
}

bool SoilContactModel::interface_at(const CellContact& c, int f, Interface* out) const {
  const double d = grid_.cell_size_m();
  const int cell = static_cast<int>(c.cell);
  const int i = c.i + kFaceStep[f][0], j = c.j + kFaceStep[f][1];
  if (c.interface_w_m[f] > 0.0) {
    out->s_m = c.interface_s_m[f];
    out->w_m = c.interface_w_m[f];
    out->depth_m = std::min(free_surface_m(cell, c.covered_fraction, c.covered_level_m),
                            free_level_cap(cell, c.covered_fraction, f)) -
                   c.bottom_z_m;
  } else {
    // A fully covered cell whose neighbour the body does not touch: the
    // interface lies on the cell edge.
    if (c.covered_fraction < kFullyCovered || !grid_.contains(i, j)) return false;
    if (map_slot(i, j) >= 0) return false;
    out->s_m = d;
    out->w_m = d;
    out->depth_m = grid_.surface_at(grid_.index(i, j)) - c.bottom_z_m;
  }
  return out->depth_m > 0.0;
}

double SoilContactModel::walk_wedge(const CellContact& c, int f, const Interface& face, double rho_rad,
                                    bool beyond_body) {
  // The fracture plane rises at rho from the interface's foot (fig. 5.15);
  // u is the horizontal distance from the interface.
  const double d = grid_.cell_size_m();
  const double t = std::tan(rho_rad);
  const double length_cap = 2.0 * face.depth_m / t;
  wedge_cells_.clear();
  wedge_area_.clear();
  // The free part of the interface's own cell.
  double u = d - face.s_m;
  double total = clipped_section(face.depth_m, t, 0.0, u);
  int i = c.i, j = c.j;
  wedge_end_surface_m_ = c.bottom_z_m + face.depth_m;
  if (beyond_body) {
    // Pushed material lands beyond the body's own cells, never under it.
    while (map_slot(i + kFaceStep[f][0], j + kFaceStep[f][1]) >= 0) {
      i += kFaceStep[f][0];
      j += kFaceStep[f][1];
    }
  }
  while (u < length_cap) {
    i += kFaceStep[f][0];
    j += kFaceStep[f][1];
    if (!grid_.contains(i, j)) break;
    const int n = grid_.index(i, j);
    if (grid_.covered(n) || map_slot(i, j) >= 0) break;
    const double a = grid_.surface_at(n) - c.bottom_z_m;
    wedge_end_surface_m_ = grid_.surface_at(n);
    const double section = clipped_section(a, t, u, u + d);
    wedge_cells_.push_back(n);
    wedge_area_.push_back(section);
    total += section;
    u += d;
    if (a < t * u) break;  // the plane came out within this cell (d_{M+1} < 0)
  }
  return total;
}

void SoilContactModel::push_material(const Push& push, const CellContact& c) {
  // (5.7): the material in the volume the interface swept slides up the
  // fracture plane; it lands on the wedge's cells in proportion to the soil
  // each holds above the plane (the cells under the fracture rise).
  Interface face;
  if (!interface_at(c, push.direction, &face)) {
    face.s_m = grid_.cell_size_m();
    face.depth_m = std::max(push.height_m, grid_.cell_size_m());
  }
  walk_wedge(c, push.direction, face, regions_[region_in_front(c, push.direction)].rho_table.rho_rad(0.0), true);
  const auto quanta = static_cast<std::int64_t>(push.height_m / kHeightQuantumM);
  const int cell = static_cast<int>(c.cell);
  if (wedge_cells_.empty()) {
    // Nothing in front but the grid's edge: off-site over an open edge.
    int i = c.i + kFaceStep[push.direction][0], j = c.j + kFaceStep[push.direction][1];
    while (map_slot(i, j) >= 0) {
      i += kFaceStep[push.direction][0];
      j += kFaceStep[push.direction][1];
    }
    if (grid_.contains(i, j)) return;  // a covered neighbour: the body holds it
    static constexpr Edge kEdgeOfFace[kFaceCount] = {kEdgeXMax, kEdgeXMin, kEdgeYMax, kEdgeYMin};
    const Edge edge = kEdgeOfFace[push.direction];
    if (grid_.spec().edges[edge] == EdgeKind::kOpen) grid_.transfer_quanta(cell, -1, quanta, edge);
    return;
  }
  double total = 0.0;
  for (double a : wedge_area_) total += a;
  const std::int64_t available = std::min(quanta, grid_.loose_quanta(cell));
  std::int64_t left = available;
  for (std::size_t k = 0; k < wedge_cells_.size(); ++k) {
    std::int64_t share = total > 0.0 ? static_cast<std::int64_t>(available * (wedge_area_[k] / total)) : 0;
    if (k == 0) share = total > 0.0 ? share : available;
    share = std::min(share, left);
    left -= grid_.transfer_quanta(cell, wedge_cells_[k], share);
  }
  if (left > 0) grid_.transfer_quanta(cell, wedge_cells_[0], left);
}

void SoilContactModel::index_map(const ContactMap& map) {
  // A small lookup over the map's bounds (contact-sized, not grid-sized).
  slot_i0_ = slot_j0_ = 0;
  slot_ni_ = slot_nj_ = 0;
  if (map.cells.empty()) return;
  int i0 = grid_.nx(), i1 = -1;
  for (const CellContact& c : map.cells) {
    i0 = std::min(i0, c.i);
    i1 = std::max(i1, c.i);
  }
  slot_i0_ = i0;
  slot_j0_ = map.cells.front().j;
  slot_ni_ = i1 - i0 + 1;
  slot_nj_ = map.cells.back().j - slot_j0_ + 1;
  slots_.assign(static_cast<std::size_t>(slot_ni_) * slot_nj_, -1);
  for (std::size_t k = 0; k < map.cells.size(); ++k)
    slots_[static_cast<std::size_t>(map.cells[k].j - slot_j0_) * slot_ni_ + (map.cells[k].i - slot_i0_)] =
        static_cast<int>(k);
}

int SoilContactModel::map_slot(int i, int j) const {
  i -= slot_i0_;
  j -= slot_j0_;
  if (i < 0 || j < 0 || i >= slot_ni_ || j >= slot_nj_) return -1;
  return slots_[static_cast<std::size_t>(j) * slot_ni_ + i];
}

void SoilContactModel::wedge_reactions(const BodyState& state, const ContactMap& map, BodyReaction& out) {
  const double gamma_g = grid_.soil().bulk_density_kg_m3 * kGravity_m_s2;
  const double d = grid_.cell_size_m();
  interfaces_.clear();
  for (std::size_t k = 0; k < map.cells.size(); ++k) {
    Interface face;
    for (int f = 0; f < kFaceCount; ++f)
      if (interface_at(map.cells[k], f, &face)) interfaces_.push_back({static_cast<int>(k), f, face});
  }
  for (int f = 0; f < kFaceCount; ++f) {
    double width = 0.0, depth_width = 0.0;
    region_width_.assign(regions_.size(), 0.0);
    for (const FaceRef& r : interfaces_) {
      if (r.direction != f) continue;
      width += r.face.w_m;
      depth_width += r.face.w_m * r.face.depth_m;
      region_width_[region_in_front(map.cells[r.contact], f)] += r.face.w_m;
    }
    if (width <= 0.0) continue;
    // One soil per wedge: the one in front of most of the interfaces' width
    // (the wedge is made of it).
    const SoilRegion& region =
        regions_[std::max_element(region_width_.begin(), region_width_.end()) - region_width_.begin()];
    WedgeReaction& w = out.wedge[f];
    w.width_m = width;
    w.depth_m = depth_width / width;
    const bool thesis = region.soil.cutting == CuttingModel::kThesisWedge;
    w.rake_rad = thesis ? 0.5 * kPi : tool_rake_rad(state, f);
    const CuttingSoil& cutting = region.cutting;
    CuttingTool tool;
    tool.depth_m = w.depth_m;
    tool.width_m = width;
    tool.rake_rad = w.rake_rad;
    // The failure plane of flat ground walks the soil actually in front.
    w.rho_rad = region.rho_table.rho_rad(w.depth_m / width);
    double cut_depth_width = 0.0;  // the tool's depth below the ground where the wedge ends, by width
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    for (const FaceRef& r : interfaces_) {
      if (r.direction != f) continue;
      const CellContact& c = map.cells[r.contact];
      const Interface& face = r.face;
      w.weight_N += gamma_g * face.w_m * walk_wedge(c, f, face, w.rho_rad, false);
      cut_depth_width += face.w_m * std::clamp(wedge_end_surface_m_ - c.bottom_z_m, 0.0, face.depth_m);
      // The interface: from the cell edge behind it, s along the direction.
      const Eigen::Vector2d centre =
          grid_.spec().origin_m + d * Eigen::Vector2d(c.i, c.j);
      Eigen::Vector3d p = c.point_m;
      const double offset = face.s_m - 0.5 * d;
      if (f < 2) p.x() = centre.x() + (f == 0 ? offset : -offset);
      else p.y() = centre.y() + (f == 2 ? offset : -offset);
      p.z() = c.bottom_z_m + face.depth_m / 3.0;  // a third of the interface height (5.5.2)
      point += face.w_m * p;
    }
    w.point_m = point / width;
    if (thesis) {
      const double side =
          wedge_side_friction_N(region.phi_rad, w.rho_rad, grid_.soil().bulk_density_kg_m3, w.depth_m);
      w.bound_N = wedge_limit_N(region.phi_rad, w.rho_rad, w.weight_N, side);
      continue;
    }
    // The equation's d is the tool's depth in the ground it cuts: below the
    // surface where the wedge ends, not the heap against the face (the
    // interfaces' H includes it). The soil above that level in the wedge is McKyes's
    // surcharge q, spread over the failure zone's length at the surface.
    tool.depth_m = cut_depth_width / width;
    if (!(tool.depth_m > 0.0)) tool.depth_m = w.depth_m;
    const CuttingForce flat = mckyes_ali(cutting, tool);
    const double length = flat.rupture_m > 0.0 ? flat.rupture_m : tool.depth_m;
    const double flat_weight = gamma_g * width * 0.5 * tool.depth_m * tool.depth_m / std::tan(w.rho_rad);
    tool.surcharge_Pa = std::max(0.0, w.weight_N - flat_weight) / (width * length);
    // The heap was weighed in front of the interfaces, over their width: it
    // loads the central wedge, not the crescents beside it.
    tool.surcharge_on_crescents = false;
    w.surcharge_Pa = tool.surcharge_Pa;
    const CuttingForce force = mckyes_ali(cutting, tool);
    if (force.failure_angle_rad > 0.0) w.rho_rad = force.failure_angle_rad;
    w.bound_N = force.horizontal_N;
    w.vertical_down_N = force.vertical_down_N;
  }
}

SoilContactModel::BodyState& SoilContactModel::body_state(int body_id) {
  if (body_id < 0 || body_id > kMaxBodyId)
    throw std::invalid_argument("SoilContactModel: body_id " + std::to_string(body_id) + " is not in [0, 65535]");
  if (body_id >= static_cast<int>(bodies_.size())) bodies_.resize(body_id + 1);
  return bodies_[body_id];
}

double SoilContactModel::untouched_level_m(int cell, double covered_fraction) const {
  // If the cell's plastic sinkage (an old imprint) lies under the part now
  // covered, that part's soil stands lower than the cell's mean.
  const double surface = grid_.surface_at(cell);
  if (plastic_.empty()) return surface;
  return surface + plastic_[cell] - plastic_sinkage_under(cell, covered_fraction);
}

void SoilContactModel::embed(int body_id, const BodyGeometry& body, const BodyMotion& motion) {
  BodyState& state = body_state(body_id);
  mapper_.build(grid_, body, motion, &state.next);
  update_covered(state);
  for (CellContact& c : state.next.cells)
    c.covered_level_m = std::min(untouched_level_m(static_cast<int>(c.cell), c.covered_fraction), c.bottom_z_m);
  std::swap(state.map, state.next);
  state.in_contact = !state.map.cells.empty();
}

BodyReaction SoilContactModel::interact(int body_id, const BodyGeometry& body, const BodyMotion& motion,
                                        bool wedge_bounds) {
  BodyState& state = body_state(body_id);
  if (state.covered.capacity() == 0) reserve_body(body_id, body.world_bounds().diagonal().norm());
  mapper_.build(grid_, body, motion, &state.next);
  BodyReaction out;
  const ContactMap& now = state.next;
  index_map(now);
  const ContactMap& before = state.map;
  if (peak_.empty() && !now.cells.empty()) {
    peak_.assign(static_cast<std::size_t>(grid_.nx()) * grid_.ny(), 0.0f);
    plastic_.assign(peak_.size(), 0.0f);
    pressed_.assign(peak_.size(), 0.0f);
  }
  current_footprint_centre_ = Eigen::Vector2d::Zero();
  if (!now.footprint.isEmpty()) current_footprint_centre_ = now.footprint.center();
  update_covered(state);
  for (SoilRegion& r : regions_) r.modulus_Pa = bekker_modulus_Pa(r.soil, now.footprint_b_m);

  pushes_.clear();
  std::size_t k = 0;
  for (CellContact& c : state.next.cells) {
    while (k < before.cells.size() && before.cells[k].cell < c.cell) ++k;
    const CellContact* previous =
        k < before.cells.size() && before.cells[k].cell == c.cell ? &before.cells[k] : nullptr;
    const int cell = static_cast<int>(c.cell);
    const double surface = grid_.surface_at(cell);
    const double untouched_level = untouched_level_m(cell, c.covered_fraction);
    double covered_before = 0.0, level_before = untouched_level;
    if (previous) {
      covered_before = previous->covered_fraction;
      level_before = previous->covered_level_m;
    }
    const double free_before = free_surface_m(cell, covered_before, level_before);
    // Advancing horizontally faster than sinking: the soil in the newly
    // covered part is pushed ahead (5.5.3), and, as in the thesis, the
    // advancing interface carries no vertical load this step.
    int direction = -1;
    double fastest = std::max(0.0, -c.velocity_m_s.z());
    for (int f = 0; f < kFaceCount; ++f) {
      if (along(c.velocity_m_s, f) > fastest) {
        fastest = along(c.velocity_m_s, f);
        direction = f;
      }
    }
    if (state.press_only) direction = -1;
    const double gained = c.covered_fraction - covered_before;
    // The covered part's level: the part covered before keeps its own; the
    // newly covered part is at the free part's level, or at the underside
    // where the body pushes the soil above it away.
    c.covered_level_m = level_before;
    double pushed = 0.0;
    if (gained > 0.0 && direction >= 0) {
      // (5.7) over the whole swept area: what the cell holds beyond its
      // covered part (now at most at the underside) and its free part (at
      // most level with the soil in front) goes ahead. With nothing else
      // that is the swept fraction times the soil above the underside,
      // (5.7); a change of cell (5.5.3) is this cell filling up and the
      // next one starting, both counted.
      const double level =
          (covered_before * level_before + gained * std::min(free_before, c.bottom_z_m)) / c.covered_fraction;
      const double free_level = std::min(free_before, free_level_cap(cell, c.covered_fraction, direction));
      const double keep = c.covered_fraction >= kFullyCovered
                              ? level
                              : c.covered_fraction * level + (1.0 - c.covered_fraction) * free_level;
      pushed = std::max(0.0, surface - keep);
      if (pushed > 0.0) c.covered_level_m = level;
    } else if (gained > 0.0) {
      c.covered_level_m = (covered_before * level_before +
                           gained * (covered_before > 0.0 ? free_before : untouched_level)) /
                          c.covered_fraction;
    }
    if (pushed > 0.0) {
      pushes_.push_back({c.cell, direction, pushed, false});
      continue;
    }
    press(c, motion, out);
  }
  state.sliced.clear();
  for (const Push& p : pushes_) {
    if (state.slicing && !p.plastic &&
        face_ahead(p.direction, state.slicing_forward.x(), state.slicing_forward.y(), 1.0)) {
      // (6.4) The edge cuts: the swept soil leaves for the body, no wedge.
      const auto wanted = static_cast<std::int64_t>(p.height_m / kHeightQuantumM);
      const std::int64_t q = grid_.export_quanta(static_cast<int>(p.cell), wanted);
      if (q > 0) state.sliced.push_back({p.cell, q});
      out.displaced_m3 += q * grid_.quantum_volume_m3();
      continue;
    }
    const auto it = std::lower_bound(state.next.cells.begin(), state.next.cells.end(), p.cell,
                                     [](const CellContact& c, std::uint32_t cell) { return c.cell < cell; });
    const std::int64_t before_push = grid_.loose_quanta(static_cast<int>(p.cell));
    push_material(p, *it);
    const std::int64_t moved = before_push - grid_.loose_quanta(static_cast<int>(p.cell));
    out.displaced_m3 += moved * grid_.quantum_volume_m3();
    if (p.plastic) record_plastic(*it, moved);
  }
  // A fully covered cell's soil stands at its surface: keep that level for
  // when the body uncovers part of it.
  for (CellContact& c : state.next.cells)
    if (c.covered_fraction >= kFullyCovered) c.covered_level_m = grid_.surface_at(static_cast<int>(c.cell));
  if (wedge_bounds) wedge_reactions(state, now, out);

  out.shear_point_m =
      out.shear_bound_N > 0.0 ? Eigen::Vector3d(out.shear_point_m / out.shear_bound_N) : motion.reference_point_m;
  out.contact_cells = static_cast<int>(now.cells.size());
  std::swap(state.map, state.next);
  state.in_contact = !state.map.cells.empty();
  return out;
}

}  // namespace skidsim::terrain
