// The granular grid's side of automata on moving bodies (thesis 6.2, 6.3;
// terrain/material_exchange.h drives these): world slopes on a tilted grid,
// exact moves in and out, what crosses the open edges, the flow angles.
#include "common/physical_constants.h"
#include "terrain/granular_grid.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace skidsim::terrain {
namespace {

// The edge a neighbour direction (+x, -x, +y, -y) crosses leaving the grid.
constexpr Edge kEdgeOfDirection[4] = {kEdgeXMax, kEdgeXMin, kEdgeYMax, kEdgeYMin};

}  // namespace

void GranularGrid::tilt_faces(FaceGeometry& g) const {
  // (6.2): the slope between two surface points is that of the vector
  // between them in the world. Face k goes +-d along one grid axis with the
  // height change -drop along z'; its world rise is its dot product with
  // world up u (in the grid frame), its run what is left of its length. The
  // slope magnitude is that of the surface's plane through this vector and
  // the tangential one, (0, d, t) or (d, 0, t): its normal n is their cross
  // product, tan^2 = (|n|^2 - (n.u)^2) / (n.u)^2, written out below (n / d).
  const double d = spec_.cell_size_m, ux = up_.x(), uy = up_.y(), uz = up_.z();
  const double floor_run2 = 1e-12 * d * d;  // a vertical vector: a huge slope, not a division by zero
  for (int k = 0; k < 4; ++k) {
    const double sign = (k % 2 == 0) ? 1.0 : -1.0;
    const double drop = g.drop[k], t = g.tangential[k];
    const double rise = sign * d * (k < 2 ? ux : uy) - drop * uz;
    const double run = std::sqrt(std::max(d * d + drop * drop - rise * rise, floor_run2));
    const double slope_along = -rise / run;
    const double n2 = drop * drop + t * t + d * d;
    const double nu = k < 2 ? drop * ux - sign * t * uy + sign * d * uz : sign * t * ux - drop * uy - sign * d * uz;
    const double tan2 = (n2 - nu * nu) / std::max(nu * nu, 1e-12 * n2);
    g.drop[k] = slope_along * d;
    g.tangential[k] = std::sqrt(std::max(0.0, tan2 - slope_along * slope_along)) * d;
  }
}

void GranularGrid::set_world_up(const Eigen::Vector3d& up_in_grid) {
  const double n = up_in_grid.norm();
  if (!(n > 0.0) || !up_in_grid.allFinite()) throw std::invalid_argument("set_world_up: the up vector must be finite and non-zero");
  up_ = up_in_grid / n;
  tilted_ = !(up_.x() == 0.0 && up_.y() == 0.0 && up_.z() == 1.0);
  // Cells at rest stay at rest under a tiny change of tilt; a larger one can
  // tip them past the threshold, so they are examined again.
  if (up_.dot(up_woken_) < std::cos(1e-3)) {
    up_woken_ = up_;
    wake_material_cells();
  }
}

void GranularGrid::set_flow_angles_deg(double repose_deg, double stop_deg) {
  if (!(stop_deg > 0.0 && stop_deg <= repose_deg && repose_deg < 89.0)) {
    std::ostringstream msg;
    msg << "flow angles repose " << repose_deg << " deg, stop " << stop_deg
        << " deg: expected 0 < stop <= repose < 89";
    throw std::invalid_argument(msg.str());
  }
  constexpr double kDeg = kPi / 180.0;
  const double tan_repose = std::tan(repose_deg * kDeg), tan_stop = std::tan(stop_deg * kDeg);
  if (tan_repose == law_.tan_repose && tan_stop == law_.tan_stop) return;
  const bool lowered = tan_repose < law_.tan_repose || tan_stop < law_.tan_stop;
  law_.tan_repose = tan_repose;
  law_.tan_stop = tan_stop;
  // The transport floor must stay under z+ tan(alpha_I) (the stability
  // bound rests on it): at most the soil's own, at most tan(alpha_I).
  law_.transport_excess = std::min(soil_.min_flow_layer_m / soil_.rolling_layer_m, tan_stop);
  if (lowered) wake_material_cells();
}

void GranularGrid::wake_material_cells() {
  for (std::uint32_t c = 0; c < quanta_.size(); ++c)
    if (quanta_[c] > 0) wake(static_cast<int>(c));
}

std::int64_t GranularGrid::export_quanta(int cell, std::int64_t quanta) {
  const std::int64_t q = std::max<std::int64_t>(0, std::min(quanta, quanta_[cell]));
  if (q == 0) return 0;
  quanta_[cell] -= q;
  take_from_top(static_cast<std::size_t>(cell), q);
  ledger_.exported += q;
  refresh_surface(cell);
  wake(cell);
  return q;
}

void GranularGrid::import_quanta(int cell, std::int64_t quanta) {
  if (quanta <= 0) return;
  quanta_[cell] += quanta;
  loosen(static_cast<std::size_t>(cell), quanta);
  ledger_.imported += quanta;
  flags_[cell] |= kFlowing;  // it arrives moving (4.5)
  refresh_surface(cell);
  wake(cell);
}

void GranularGrid::capture_edge_outflow(bool on) {
  capture_edges_ = on;
  if (on && edge_outflow_.empty()) {
    edge_outflow_.assign(static_cast<std::size_t>(edge_slot_count()), 0);
    edge_neighbour_m_.assign(static_cast<std::size_t>(edge_slot_count()), std::numeric_limits<double>::quiet_NaN());
  }
}

int GranularGrid::edge_slot(int i, int j, int direction) const {
  switch (direction) {
    case 0: return j;
    case 1: return spec_.ny + j;
    case 2: return 2 * spec_.ny + i;
    default: return 2 * spec_.ny + spec_.nx + i;
  }
}

void GranularGrid::edge_slot_cell(int slot, int* i, int* j, int* direction) const {
  const int nx = spec_.nx, ny = spec_.ny;
  if (slot < ny) {
    *i = nx - 1, *j = slot, *direction = 0;
  } else if (slot < 2 * ny) {
    *i = 0, *j = slot - ny, *direction = 1;
  } else if (slot < 2 * ny + nx) {
    *i = slot - 2 * ny, *j = ny - 1, *direction = 2;
  } else {
    *i = slot - 2 * ny - nx, *j = 0, *direction = 3;
  }
}

std::int64_t GranularGrid::pending_edge_outflow() const {
  std::int64_t total = 0;
  for (std::int64_t q : edge_outflow_) total += q;
  return total;
}

void GranularGrid::send_over_edge(std::uint32_t cell, int direction, std::int64_t quanta) {
  if (!capture_edges_) {
    ledger_.off_site[kEdgeOfDirection[direction]] += quanta;
    return;
  }
  const int i = static_cast<int>(cell % static_cast<std::uint32_t>(spec_.nx));
  const int j = static_cast<int>(cell / static_cast<std::uint32_t>(spec_.nx));
  edge_outflow_[static_cast<std::size_t>(edge_slot(i, j, direction))] += quanta;
  ledger_.exported += quanta;
}

}  // namespace skidsim::terrain
