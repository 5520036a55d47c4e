#include "terrain/momentum_flow.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace skidsim::terrain {
namespace {

double tan_deg(double deg) { return std::tan(deg_to_rad(deg)); }

// Directions +x, -x, +y, -y as (di, dj), and the grid edge each crosses.
constexpr int kDi[4] = {1, -1, 0, 0};
constexpr int kDj[4] = {0, 0, 1, -1};
constexpr Edge kEdgeOf[4] = {kEdgeXMax, kEdgeXMin, kEdgeYMax, kEdgeYMin};

// The neighbour of (i, j) towards direction k: its cell index, -1 beyond an
// open edge (a drop-off), -2 beyond a closed edge or into a covered cell (a wall).
int neighbour(const GranularGrid& g, int i, int j, int k) {
  const int ni = i + kDi[k], nj = j + kDj[k];
  if (!g.contains(ni, nj)) return g.spec().edges[kEdgeOf[k]] == EdgeKind::kOpen ? -1 : -2;
  const int c = g.index(ni, nj);
  return g.covered(c) ? -2 : c;
}

}  // namespace

namespace {
// Savage-Hutter (2.23) with sign -1 (active) or +1 (passive).
double earth_pressure(double phi_deg, double delta_deg, double sign) {
  const double c = std::cos(deg_to_rad(phi_deg)), cd = std::cos(deg_to_rad(std::min(delta_deg, phi_deg)));
  return 2.0 / (c * c) * (1.0 + sign * std::sqrt(std::max(0.0, 1.0 - c * c / (cd * cd)))) - 1.0;
}
}  // namespace

double earth_pressure_active(double phi_deg, double delta_deg) { return earth_pressure(phi_deg, delta_deg, -1.0); }
double earth_pressure_passive(double phi_deg, double delta_deg) { return earth_pressure(phi_deg, delta_deg, 1.0); }

MomentumFlow::MomentumFlow(const GranularGrid& grid, const MomentumFlowParameters& params, double step_dt_s)
    : step_dt_s_(step_dt_s), d_(grid.cell_size_m()), courant_(params.courant), max_substeps_(params.max_substeps) {
  const SoilFlowParameters& soil = grid.soil();
  const double bed_deg = params.bed_friction_deg > 0.0 ? params.bed_friction_deg : soil.stop_angle_deg;
  const double start_deg = params.start_friction_deg > 0.0 ? params.start_friction_deg : soil.repose_angle_deg;
  if (!(bed_deg > 0.0 && bed_deg < 89.0 && start_deg >= bed_deg && start_deg < 89.0))
    throw std::invalid_argument("momentum flow: bed friction must be in (0, 89) deg and at most the start friction");
  if (!(courant_ > 0.0 && courant_ <= 0.5)) throw std::invalid_argument("momentum flow: courant must be in (0, 0.5]");
  mu_ = tan_deg(bed_deg);
  if (params.side_wall_gap_m > 0.0) {
    if (!(params.side_wall_friction_deg >= 0.0 && params.side_wall_friction_deg < 89.0))
      throw std::invalid_argument("momentum flow: side_wall_friction_deg must be in [0, 89)");
    wall_mu_over_gap_ = tan_deg(params.side_wall_friction_deg) / params.side_wall_gap_m;
  }
  mu_start_ = tan_deg(start_deg);
  if (params.earth_pressure > 0.0) {
    k_active_ = k_passive_ = params.earth_pressure;
  } else {
    k_active_ = terrain::earth_pressure_active(soil.repose_angle_deg, bed_deg);
    k_passive_ = terrain::earth_pressure_passive(soil.repose_angle_deg, bed_deg);
  }
  // The stability bound: donor-cell transport keeps h >= 0 and moves no
  // material past a neighbour while (|u| + |v|) dt / d <= 1; the explicit
  // pressure term asks the gravity waves' speed sqrt(g K h) into the same
  // Courant number (Savage-Hutter's characteristic speeds u +- sqrt(g K h)).
  // No material falls faster than from the tallest column's whole height.
  double tallest = 0.0, lowest = 1e300, highest = -1e300;
  for (int j = 0; j < grid.ny(); ++j)
    for (int i = 0; i < grid.nx(); ++i) {
      tallest = std::max(tallest, grid.material_m(i, j));
      lowest = std::min(lowest, grid.base_m(i, j));
      highest = std::max(highest, grid.surface_m(i, j));
    }
  const double drop = std::max(tallest, highest - lowest);
  const double fastest = std::sqrt(2.0 * kGravity_m_s2 * drop) * std::sqrt(2.0) + std::sqrt(kGravity_m_s2 * k_passive_ * tallest);
  const double needed = std::max(1.0, std::ceil(fastest * step_dt_s_ / (courant_ * d_) - 1e-12));
  if (!(needed <= max_substeps_)) {
    std::ostringstream msg;
    msg << "momentum flow: a fall of " << drop << " m reaches " << fastest << " m/s, which at cell size " << d_
        << " m and step " << step_dt_s_ << " s needs " << needed << " sub-steps for Courant number " << courant_
        << " (limit " << max_substeps_ << "). Use larger cells or allow more sub-steps.";
    throw std::invalid_argument(msg.str());
  }
  const std::size_t n = static_cast<std::size_t>(grid.nx()) * grid.ny();
  ux_.assign(n, 0.0);
  uy_.assign(n, 0.0);
  listed_.assign(n, 0);
  mom_x_.assign(n, 0.0);
  mom_y_.assign(n, 0.0);
  flowing_.assign(n, 0);
  arriving_.assign(n, 0);
  leaving_.assign(n, 0);
  tan_stop_ = tan_deg(soil.stop_angle_deg);
  min_layer_m_ = soil.min_flow_layer_m;
}

void MomentumFlow::mark(int cell) {
  if (listed_[cell]) return;
  listed_[cell] = 1;
  candidates_.push_back(cell);
}

void MomentumFlow::wake_all(const GranularGrid& grid) {
  for (int c = 0; c < grid.nx() * grid.ny(); ++c)
    if (grid.loose_quanta(c) > 0) mark(c);
}

double MomentumFlow::speed_m_s(int cell) const { return std::hypot(ux_[cell], uy_[cell]); }

void MomentumFlow::step(GranularGrid& grid) {
  last_substeps_ = 0;
  if (moving_.empty() && candidates_.empty()) return;  // at rest: nothing to do
  // Sub-steps for the fastest signal among the moving cells and the
  // candidates (Courant number courant_), within the bound checked at
  // construction.
  double fastest = 0.0;
  auto signal = [&](int c) {
    const double h = grid.loose_quanta(c) * kHeightQuantumM;
    return std::abs(ux_[c]) + std::abs(uy_[c]) + std::sqrt(kGravity_m_s2 * k_passive_ * h);
  };
  for (int c : moving_) fastest = std::max(fastest, signal(c));
  for (int c : candidates_) fastest = std::max(fastest, signal(c));
  const int n = std::clamp(static_cast<int>(std::ceil(fastest * step_dt_s_ / (courant_ * d_) - 1e-12)), 1, max_substeps_);
  for (int s = 0; s < n && !(moving_.empty() && candidates_.empty()); ++s) {
    substep(grid, step_dt_s_ / n);
    ++last_substeps_;
  }
}

void MomentumFlow::substep(GranularGrid& grid, double dt_s) {
  // The cells to examine: the moving ones, their neighbours and the woken ones.
  for (int c : moving_) {
    mark(c);
    const int i = c % grid.nx(), j = c / grid.nx();
    for (int k = 0; k < 4; ++k) {
      const int nb = neighbour(grid, i, j, k);
      if (nb >= 0) mark(nb);
    }
  }
  accelerate(grid, dt_s);
  transport(grid, dt_s);
  for (int c : candidates_) listed_[c] = 0;
  candidates_.clear();
}

void MomentumFlow::accelerate(const GranularGrid& grid, double dt_s) {
  // New flowing layers and velocities from the old state (every cell read
  // before any is written: the result does not depend on the list's order).
  outs_.clear();
  for (int c : candidates_) {
    const std::int64_t q = grid.loose_quanta(c);
    if (q <= 0) continue;
    const int i = c % grid.nx(), j = c / grid.nx();
    const double b = grid.base_at(c), h_surface = grid.surface_at(c);
    const std::int64_t flowing_old = std::min(flowing_[c], q);
    // Neighbours' surface, flowing layer and velocity; a wall mirrors the
    // cell (no gradient across it, the velocity reflected), a drop-off is
    // bare base at the cell's own level.
    double nb_h[4], nb_f[4], nb_u[4];
    for (int k = 0; k < 4; ++k) {
      const int nb = neighbour(grid, i, j, k);
      const double own_u = k < 2 ? ux_[c] : uy_[c];
      if (nb >= 0) {
        nb_h[k] = grid.surface_at(nb), nb_f[k] = std::min(flowing_[nb], grid.loose_quanta(nb)) * kHeightQuantumM;
        nb_u[k] = k < 2 ? ux_[nb] : uy_[nb];
      } else {
        nb_h[k] = nb == -1 ? b : h_surface, nb_f[k] = nb == -1 ? 0.0 : flowing_old * kHeightQuantumM;
        nb_u[k] = nb == -1 ? own_u : -own_u;
      }
    }
    // Failure (erosion): across a face steeper than the start angle (or the
    // stop angle, where the layer already flows) the material above the
    // stop-angle plane through the pair's mid-point fails and joins the
    // flowing layer; the static soil under it stays.
    const bool flows = flowing_old > 0;
    double failing = 0.0;
    for (int k = 0; k < 4; ++k) {
      const double drop = h_surface - nb_h[k];
      if (drop > d_ * (flows ? tan_stop_ : mu_start_)) failing = std::max(failing, 0.5 * (drop - d_ * tan_stop_));
    }
    const std::int64_t flowing =
        std::min(q, std::max(flowing_old, static_cast<std::int64_t>(std::llround(failing / kHeightQuantumM))));
    // A layer thinner than h_stop does not flow (Pouliquen 1999; the soil's
    // min_flow_layer_m, the automaton's transport layer): it lies down, and
    // the automaton's slow regime has it.
    if (flowing == 0 || flowing * kHeightQuantumM < min_layer_m_) continue;
    const double divergence = (nb_u[0] - nb_u[1] + nb_u[2] - nb_u[3]) / (2.0 * d_);
    const double k_earth = divergence >= 0.0 ? k_active_ : k_passive_;
    const double f = flowing * kHeightQuantumM;
    // -g (grad H + (K - 1) grad f): the layer feels the surface's slope, and
    // its own thickness's through the earth pressure (K = 1: hydrostatic).
    const double ax = -kGravity_m_s2 * ((nb_h[0] - nb_h[1]) + (k_earth - 1.0) * (nb_f[0] - nb_f[1])) / (2.0 * d_);
    const double ay = -kGravity_m_s2 * ((nb_h[2] - nb_h[3]) + (k_earth - 1.0) * (nb_f[2] - nb_f[3])) / (2.0 * d_);
    double ux = ux_[c] + ax * dt_s, uy = uy_[c] + ay * dt_s;
    // Coulomb friction on the bed (and the side walls) takes mu g dt of
    // speed a step; the layer stops, and lies down as static soil, when that
    // is all it has.
    const double speed = std::hypot(ux, uy), loss = (mu_ + wall_mu_over_gap_ * f) * kGravity_m_s2 * dt_s;
    const double keep = speed > loss ? (speed - loss) / speed : 0.0;
    if (keep == 0.0) continue;
    outs_.push_back({c, {0, 0, 0, 0}, ux * keep, uy * keep, flowing});
  }
  for (int c : candidates_) ux_[c] = uy_[c] = 0.0, flowing_[c] = 0;
  for (const Out& o : outs_) ux_[o.cell] = o.ux, uy_[o.cell] = o.uy, flowing_[o.cell] = o.flowing;
}

void MomentumFlow::transport(GranularGrid& grid, double dt_s) {
  // Donor cell: a moving cell sends h |u| dt / d along the sign of each
  // component, rounded to quanta, from the state before the sub-step.
  for (Out& o : outs_) {
    const int c = o.cell, i = c % grid.nx(), j = c / grid.nx();
    const std::int64_t q = o.flowing;
    const double frac[4] = {std::max(o.ux, 0.0), std::max(-o.ux, 0.0), std::max(o.uy, 0.0), std::max(-o.uy, 0.0)};
    std::int64_t total = 0;
    for (int k = 0; k < 4; ++k) {
      if (frac[k] == 0.0) continue;
      if (neighbour(grid, i, j, k) == -2) {
        // A wall stops the component into it (an inelastic wall).
        if (k < 2) ux_[c] = o.ux = 0.0;
        else uy_[c] = o.uy = 0.0;
        continue;
      }
      o.q[k] = std::llround(static_cast<double>(q) * frac[k] * dt_s / d_);
      total += o.q[k];
    }
    if (total > q)  // only past the Courant bound; scale down, exactly within q
      for (int k = 0; k < 4; ++k) o.q[k] = o.q[k] * q / total;
  }
  // Momentum goes with the flowing material: what stays keeps its velocity,
  // what arrives joins the receiver's flowing layer with its donor's.
  std::vector<int>& touched = moving_;
  touched.clear();
  for (const Out& o : outs_) {
    const int c = o.cell, i = c % grid.nx(), j = c / grid.nx();
    std::int64_t sent = 0;
    for (int k = 0; k < 4; ++k) sent += o.q[k];
    leaving_[c] += sent;
    touched.push_back(c);
    for (int k = 0; k < 4; ++k) {
      if (o.q[k] == 0) continue;
      const int nb = neighbour(grid, i, j, k);
      if (nb < 0) continue;
      mom_x_[nb] += static_cast<double>(o.q[k]) * o.ux;
      mom_y_[nb] += static_cast<double>(o.q[k]) * o.uy;
      arriving_[nb] += o.q[k];
      touched.push_back(nb);
    }
  }
  // Every donor holds what it sends (its outflows come from its own flowing
  // layer before the sub-step, and inflows only add).
  for (const Out& o : outs_) {
    const int c = o.cell, i = c % grid.nx(), j = c / grid.nx();
    for (int k = 0; k < 4; ++k)
      if (o.q[k] != 0) grid.transfer_quanta(c, neighbour(grid, i, j, k), o.q[k], kEdgeOf[k]);
  }
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  // The flowing layer's new velocity: its momentum over its mass. Cells
  // whose layer left, stopped or thinned below h_stop drop out of the moving
  // list (their material lies down).
  std::size_t kept = 0;
  for (int c : touched) {
    const std::int64_t before = flowing_[c];
    const std::int64_t stays = before - leaving_[c];
    const std::int64_t after = std::min(grid.loose_quanta(c), stays + arriving_[c]);
    const double mx = static_cast<double>(stays) * ux_[c] + mom_x_[c];
    const double my = static_cast<double>(stays) * uy_[c] + mom_y_[c];
    mom_x_[c] = mom_y_[c] = 0.0;
    arriving_[c] = leaving_[c] = 0;
    flowing_[c] = std::max<std::int64_t>(after, 0);
    ux_[c] = flowing_[c] > 0 ? mx / static_cast<double>(flowing_[c]) : 0.0;
    uy_[c] = flowing_[c] > 0 ? my / static_cast<double>(flowing_[c]) : 0.0;
    if (flowing_[c] > 0 && flowing_[c] * kHeightQuantumM >= min_layer_m_ && (ux_[c] != 0.0 || uy_[c] != 0.0))
      touched[kept++] = c;
    else ux_[c] = uy_[c] = 0.0, flowing_[c] = 0;
  }
  touched.resize(kept);
}

}  // namespace skidsim::terrain
