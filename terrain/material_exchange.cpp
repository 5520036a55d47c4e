#include "common/physical_constants.h"
#include "terrain/material_exchange.h"

#include "terrain/contact_map.h"  // kFaceStep: the automaton's neighbour order

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace skidsim::terrain {
namespace {

// What crosses a body's edge gathers for this many steps before it falls as
// one parcel (10 ms at 2 ms): a stream of parcels a few mm apart, not one per
// step and slot.
constexpr long kEmitEverySteps = 5;
// A floor steeper than ~85 deg can no longer hold anything (6.2: material
// would overhang): the body sheds all it holds.
constexpr double kShedBelowUpZ = 0.087;
// Held slices go in even without a cell of advance once slicing has
// stopped for this long.
constexpr double kFlushAfterS = 0.1;

}  // namespace

MaterialExchange::MaterialExchange(GranularGrid* ground, double step_dt_s, std::size_t max_parcels)
    : ground_(ground), dt_s_(step_dt_s), max_parcels_(std::max<std::size_t>(max_parcels, 1)) {
  if (!(step_dt_s > 0.0)) throw std::invalid_argument("MaterialExchange: step_dt_s must be > 0");
  if (ground_) {
    cell_size_m_ = ground_->cell_size_m();
    quantum_mass_kg_ = ground_->quantum_mass_kg();
  }
  parcels_.reserve(max_parcels_);
}

int MaterialExchange::add_body(BodyAutomaton* body) {
  if (!body) throw std::invalid_argument("MaterialExchange::add_body: null body");
  const GranularGrid& g = body->grid();
  if (cell_size_m_ == 0.0) {
    cell_size_m_ = g.cell_size_m();
    quantum_mass_kg_ = g.quantum_mass_kg();
  }
  if (g.cell_size_m() != cell_size_m_ || g.quantum_mass_kg() != quantum_mass_kg_) {
    std::ostringstream msg;
    msg << "MaterialExchange::add_body: a body automaton of " << g.cell_size_m() << " m cells and "
        << g.soil().bulk_density_kg_m3 << " kg/m^3 cannot exchange exactly with automata of " << cell_size_m_
        << " m cells and the same material: use the scene's cell size and soil";
    throw std::invalid_argument(msg.str());
  }
  Body b;
  b.automaton = body;
  b.slice_by_column.assign(static_cast<std::size_t>(g.ny()), 0);
  bodies_.push_back(std::move(b));
  return static_cast<int>(bodies_.size()) - 1;
}

void MaterialExchange::set_cutting_edge(int k, const CuttingEdge& edge) {
  if (!(edge.capacity_m3 > 0.0 && edge.filling_angle_drop_deg >= 0.0 && edge.filling_hold_s >= 0.0))
    throw std::invalid_argument("cutting edge: capacity_m3 must be > 0, the angle drop and hold >= 0");
  Body& b = bodies_.at(static_cast<std::size_t>(k));
  b.cutting = true;
  b.edge = edge;
}

void MaterialExchange::add_sliced(int k, int ground_cell, std::int64_t quanta) {
  if (quanta <= 0 || !ground_) return;
  Body& b = bodies_[static_cast<std::size_t>(k)];
  const BodyAutomaton& a = *b.automaton;
  const int ny = a.grid().ny();
  const GridSpec& gs = ground_->spec();
  const int gi = ground_cell % gs.nx, gj = ground_cell / gs.nx;
  const Eigen::Vector3d at(gs.origin_m.x() + gi * gs.cell_size_m, gs.origin_m.y() + gj * gs.cell_size_m,
                           ground_->surface_at(ground_cell));
  // The column of the frontier row the soil was cut in front of, the side
  // walls excluded.
  const Eigen::Vector3d local = a.inverse_pose() * at;
  const int lo = ny >= 3 ? 1 : 0, hi = ny >= 3 ? ny - 2 : ny - 1;
  const double column = std::floor(local.y() / a.grid().cell_size_m());  // clamped as a double: no overflow
  const int j = std::isfinite(column) ? static_cast<int>(std::clamp(column, double(lo), double(hi))) : lo;
  b.slice_by_column[static_cast<std::size_t>(j)] += quanta;
  b.slice_total += quanta;
  b.since_slice_s = 0.0;
  stats_.quanta_sliced += quanta;
}

void MaterialExchange::step() {
  ++steps_;
  for (int k = 0; k < body_count(); ++k) {
    if (bodies_[static_cast<std::size_t>(k)].automaton->geometric_up().z() < kShedBelowUpZ) shed_all(k);
    if (steps_ % kEmitEverySteps == 0) emit_edges(k);
    if (ground_) flow_over_edges(k);
    if (bodies_[static_cast<std::size_t>(k)].cutting) feed_frontier(k);
  }
  move_parcels();
}

void MaterialExchange::set_ground_flow(MomentumFlow* flow) {
  ground_flow_ = flow;
}

void MaterialExchange::set_firm_ground_plane(const Eigen::Vector3d& normal, double offset_m) {
  if (!(normal.allFinite() && normal.z() > 0.0 && std::isfinite(offset_m)))
    throw std::invalid_argument("MaterialExchange: the firm ground's normal must point up and be finite");
  firm_normal_ = normal.normalized();
  firm_offset_m_ = offset_m;
}

bool MaterialExchange::ground_cell(const Eigen::Vector3d& at, int* i, int* j) const {
  if (!ground_) return false;
  const GridSpec& gs = ground_->spec();
  const double fi = std::floor((at.x() - gs.origin_m.x()) / gs.cell_size_m + 0.5);
  const double fj = std::floor((at.y() - gs.origin_m.y()) / gs.cell_size_m + 0.5);
  if (!(fi >= 0.0 && fj >= 0.0 && fi < gs.nx && fj < gs.ny)) return false;
  *i = static_cast<int>(fi);
  *j = static_cast<int>(fj);
  return true;
}

void MaterialExchange::spawn(const Eigen::Vector3d& at, const Eigen::Vector3d& velocity, std::int64_t quanta,
                             int from_body) {
  if (quanta <= 0) return;
  ++stats_.parcels_spawned;
  FallingParcel p{at, velocity, quanta, from_body};
  if (parcels_.size() >= max_parcels_) {
    // No room to let it fall: it lands where it would come to rest straight
    // below (counted; the list is sized so that this does not happen in a
    // loader's work).
    ++stats_.parcels_forced;
    land(p);
    return;
  }
  parcels_.push_back(p);
  stats_.parcels_in_flight_peak = std::max<std::int64_t>(stats_.parcels_in_flight_peak, static_cast<std::int64_t>(parcels_.size()));
}

void MaterialExchange::emit_edges(int k) {
  BodyAutomaton& a = *bodies_[static_cast<std::size_t>(k)].automaton;
  GranularGrid& g = a.grid();
  for (int slot = 0; slot < g.edge_slot_count(); ++slot) {
    const std::int64_t q = g.take_edge_outflow(slot);
    if (q == 0) continue;
    int i = 0, j = 0, dir = 0;
    g.edge_slot_cell(slot, &i, &j, &dir);
    // The imaginary neighbour (6.3.2): one cell out, at the border cell's
    // base; the material leaves from there with the body's velocity.
    const Eigen::Vector3d at = a.world_point(i + kFaceStep[dir][0], j + kFaceStep[dir][1], g.base_m(i, j));
    stats_.quanta_over_edge[dir] += q;
    spawn(at, a.velocity_at(at), q, k);
  }
}

void MaterialExchange::shed_all(int k) {
  BodyAutomaton& a = *bodies_[static_cast<std::size_t>(k)].automaton;
  GranularGrid& g = a.grid();
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i) {
      const int cell = g.index(i, j);
      if (g.loose_quanta(cell) == 0) continue;
      const Eigen::Vector3d at = a.world_point(i, j, g.base_m(i, j) + 0.5 * g.material_m(i, j));
      const std::int64_t q = g.export_quanta(cell, g.loose_quanta(cell));
      stats_.quanta_shed += q;
      spawn(at, a.velocity_at(at), q, k);
    }
}

void MaterialExchange::flow_over_edges(int k) {
  // (6.3.3) Where the ground's surface under an imaginary neighbour has
  // reached the border cell's base, the ground cell takes the border cell as
  // its neighbour: it sends material up by the ground's rule, towards the
  // border cell's surface.
  const Body& body = bodies_[static_cast<std::size_t>(k)];
  // A full bucket takes nothing more over its rims: what stands above it
  // is pushed, and what runs onto the heap runs off again.
  const bool takes_more = !(body.cutting && body.choked);
  BodyAutomaton& a = *body.automaton;
  GranularGrid& g = a.grid();
  const FlowLaw& law = ground_->flow_law();
  const double d = ground_->cell_size_m();
  for (int slot = 0; slot < g.edge_slot_count(); ++slot) {
    int i = 0, j = 0, dir = 0;
    g.edge_slot_cell(slot, &i, &j, &dir);
    const Eigen::Vector3d at = a.world_point(i + kFaceStep[dir][0], j + kFaceStep[dir][1], g.base_m(i, j));
    g.set_edge_neighbour_height(slot, std::numeric_limits<double>::quiet_NaN());
    int gi = 0, gj = 0;
    if (!ground_cell(at, &gi, &gj)) continue;
    const double ground_surface = ground_->surface_m(gi, gj);
    if (ground_surface <= at.z()) continue;  // still below the upper base
    // The ground cell is the border cell's neighbour now (6.3.2): nothing
    // runs out over the edge into soil standing higher.
    const double up_z = a.geometric_up().z();
    if (up_z > 0.087) g.set_edge_neighbour_height(slot, g.base_m(i, j) + (ground_surface - at.z()) / up_z);
    if (!takes_more) continue;
    const double upper_surface = a.surface_world_z(i, j);
    const double rise = ground_surface - upper_surface;
    if (rise <= 0.0) continue;
    const double tan_beta = rise / d;
    const double threshold = ground_->flowing(gi, gj) ? law.tan_stop : law.tan_repose;
    if (tan_beta <= threshold) continue;
    const double moved_m = std::min(law.moved_height_m(tan_beta) * law.substeps, 0.5 * rise);
    const auto wanted = static_cast<std::int64_t>(moved_m / kHeightQuantumM);
    const std::int64_t q = ground_->export_quanta(ground_->index(gi, gj), wanted);
    g.import_quanta(g.index(i, j), q);
    stats_.quanta_over_lip += q;
  }
}

void MaterialExchange::feed_frontier(int k) {
  // (6.4.2) What the edge sliced waits until the body has advanced one of
  // its cells, then enters the frontier row as if the material had slid
  // back along the floor; the lowered angles let it run on inwards.
  Body& b = bodies_[static_cast<std::size_t>(k)];
  BodyAutomaton& a = *b.automaton;
  GranularGrid& g = a.grid();
  const double d = g.cell_size_m();
  b.since_slice_s += dt_s_;
  b.since_filling_s += dt_s_;
  const double volume = g.total_volume_m3();
  if (!b.choked && volume >= b.edge.capacity_m3) b.choked = true;
  if (b.choked && volume < CuttingEdge::kReopenFraction * b.edge.capacity_m3) b.choked = false;
  Eigen::Vector3d forward = a.pose().linear().col(0);
  forward.z() = 0.0;
  if (forward.norm() > 1e-6) {
    const Eigen::Vector3d lip = a.world_point(g.nx() - 1, 0.5 * (g.ny() - 1), 0.0);
    b.advance_m += std::max(0.0, a.velocity_at(lip).dot(forward.normalized())) * dt_s_;
  }
  if (b.slice_total > 0 && (b.advance_m >= d || b.since_slice_s > kFlushAfterS)) {
    // (6.4.2) The frontier row takes what was cut; the lowered angles let
    // it run on inwards. (The thesis also shifts the whole load back one
    // cell at each deposit; that piles it against the back wall and over
    // it, so the avalanches alone carry it in here.)
    for (int j = 0; j < g.ny(); ++j) {
      std::int64_t& q = b.slice_by_column[static_cast<std::size_t>(j)];
      g.import_quanta(g.index(g.nx() - 1, j), q);
      q = 0;
    }
    b.slice_total = 0;
    b.since_filling_s = 0.0;
  }
  if (b.advance_m >= d) b.advance_m = std::fmod(b.advance_m, d);
  // While the edge cuts, what stands in front of the frontier row is the
  // uncut face it is driving into: nothing runs out over the lip.
  if (b.since_slice_s < b.edge.filling_hold_s)
    for (int j = 0; j < g.ny(); ++j) g.set_edge_neighbour_height(g.edge_slot(g.nx() - 1, j, 0), kMaxColumnM);
  const SoilFlowParameters& soil = g.soil();
  if (b.since_filling_s < b.edge.filling_hold_s) {
    const double drop = b.edge.filling_angle_drop_deg;
    g.set_flow_angles_deg(std::max(1.0, soil.repose_angle_deg - drop), std::max(0.5, soil.stop_angle_deg - drop));
  } else {
    g.set_flow_angles_deg(soil.repose_angle_deg, soil.stop_angle_deg);
  }
}

void MaterialExchange::move_parcels() {
  for (std::size_t n = 0; n < parcels_.size();) {
    FallingParcel& p = parcels_[n];
    const double previous_z = p.position_m.z();
    p.velocity_m_s.z() -= kGravity_m_s2 * dt_s_;  // semi-implicit Euler: exact fall time to O(dt)
    p.position_m += p.velocity_m_s * dt_s_;
    // Lands on the highest surface it has reached this step.
    double best = -std::numeric_limits<double>::infinity();
    int target_body = -2;  // -1: the ground
    int ti = 0, tj = 0;
    for (int k = 0; k < body_count(); ++k) {
      const BodyAutomaton& a = *bodies_[static_cast<std::size_t>(k)].automaton;
      int i = 0, j = 0;
      if (!a.cell_under(p.position_m, &i, &j)) continue;
      const double surface = a.surface_world_z(i, j);
      const double base = a.world_point(i, j, a.grid().base_m(i, j)).z();
      // Reached from above only (not a body passing over a parcel under it).
      if (p.position_m.z() <= surface && previous_z >= base - cell_size_m_ && surface > best) {
        best = surface;
        target_body = k;
        ti = i;
        tj = j;
      }
    }
    bool landed = target_body >= 0;
    if (!landed) {
      int gi = 0, gj = 0;
      if (ground_cell(p.position_m, &gi, &gj)) {
        const double surface_m = ground_->surface_m(gi, gj);
        double layer_m = 0.0;
        // (above the surface it falls on; one that will press lands on the
        // bed under the layer, MomentumFlow::landing_presses)
        if (ground_flow_ && p.position_m.z() <= surface_m && ground_flow_->landing_presses(p.velocity_m_s.z())) {
          const int cell = ground_->index(gi, gj);
          layer_m = ground_flow_->flowing_m(cell) + ground_flow_->raining_m(cell);
        }
        if (p.position_m.z() <= surface_m - layer_m) {
          landed = true;
          target_body = -1;
          ti = gi;
          tj = gj;
        }
      } else if (below_firm_ground(p.position_m) || p.position_m.z() < -1000.0) {  // (no plane: it rests far down)
        landed = true;
        target_body = ground_ ? -3 : -4;  // beside the site, or on firm ground
      }
    }
    if (!landed) {
      ++n;
      continue;
    }
    if (target_body >= 0) {
      GranularGrid& g = bodies_[static_cast<std::size_t>(target_body)].automaton->grid();
      g.import_quanta(g.index(ti, tj), p.quanta);
    } else if (target_body == -1) {
      land_on_ground(ground_->index(ti, tj), p);
    } else if (target_body == -3) {
      off_site_ += p.quanta;
    } else {
      on_firm_ground_ += p.quanta;
    }
    ++stats_.parcels_landed;
    p = parcels_.back();
    parcels_.pop_back();
  }
}

void MaterialExchange::land_on_ground(int cell, const FallingParcel& p) {
  ground_->import_quanta(cell, p.quanta);
  if (ground_flow_) ground_flow_->land(*ground_, cell, p.quanta, p.velocity_m_s.x(), p.velocity_m_s.y(), p.velocity_m_s.z());
}

void MaterialExchange::land(const FallingParcel& p) {
  // Straight down from where it is: the highest automaton surface below it
  // (not the body it leaves), else the ground, else firm ground.
  double best = -std::numeric_limits<double>::infinity();
  int target = -1, ti = 0, tj = 0;
  for (int k = 0; k < body_count(); ++k) {
    const BodyAutomaton& a = *bodies_[static_cast<std::size_t>(k)].automaton;
    int i = 0, j = 0;
    if (k == p.from_body || !a.cell_under(p.position_m, &i, &j)) continue;
    const double surface = a.surface_world_z(i, j);
    if (surface <= p.position_m.z() + cell_size_m_ && surface > best) {
      best = surface;
      target = k;
      ti = i;
      tj = j;
    }
  }
  ++stats_.parcels_landed;
  if (target >= 0) {
    GranularGrid& g = bodies_[static_cast<std::size_t>(target)].automaton->grid();
    g.import_quanta(g.index(ti, tj), p.quanta);
    return;
  }
  int gi = 0, gj = 0;
  if (ground_cell(p.position_m, &gi, &gj)) {
    land_on_ground(ground_->index(gi, gj), p);
  } else if (ground_) {
    off_site_ += p.quanta;
  } else {
    on_firm_ground_ += p.quanta;
  }
}

std::int64_t MaterialExchange::in_flight_quanta() const {
  std::int64_t total = 0;
  for (const FallingParcel& p : parcels_) total += p.quanta;
  return total;
}

std::int64_t MaterialExchange::held_slice_quanta() const {
  std::int64_t total = 0;
  for (const Body& b : bodies_) total += b.slice_total;
  return total;
}

std::int64_t MaterialExchange::total_quanta() const {
  std::int64_t total = in_flight_quanta() + held_slice_quanta() + on_firm_ground_ + off_site_;
  if (ground_) total += ground_->total_quanta() + ground_->ledger().off_site_total();
  for (const Body& b : bodies_) {
    const GranularGrid& g = b.automaton->grid();
    total += g.total_quanta() + g.ledger().off_site_total() + g.pending_edge_outflow();
  }
  return total;
}

}  // namespace skidsim::terrain
