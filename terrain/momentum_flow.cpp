#include "terrain/momentum_flow.h"
#include "common/physical_constants.h"
#include "terrain/momentum_flow_cells.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace skidsim::terrain {

using namespace momentum_cells;

namespace {

double tan_deg(double deg) { return std::tan(deg_to_rad(deg)); }

// The stability bound on a sub-step's Courant number (docs/fast_flows.md,
// "Stability bound").
constexpr double kCourantBound = 0.5;

// Savage-Hutter (2.23) with sign -1 (active) or +1 (passive).
double earth_pressure(double phi_deg, double delta_deg, double sign) {
  const double c = std::cos(deg_to_rad(phi_deg)), cd = std::cos(deg_to_rad(std::min(delta_deg, phi_deg)));
  return 2.0 / (c * c) * (1.0 + sign * std::sqrt(std::max(0.0, 1.0 - c * c / (cd * cd)))) - 1.0;
}

}  // namespace

double earth_pressure_active(double phi_deg, double delta_deg) { return earth_pressure(phi_deg, delta_deg, -1.0); }
double earth_pressure_passive(double phi_deg, double delta_deg) { return earth_pressure(phi_deg, delta_deg, 1.0); }

MomentumFlowParameters session_flow_parameters(MomentumFlowParameters p) {
  p.owns_cells = true;
  p.deposition = MomentumFlowParameters::Deposition::kMeanSpeed;
  p.front_feed = MomentumFlowParameters::FrontFeed::kTaper;
  p.laid_down_holds = true;
  p.gather_steps = true;
  return p;
}

double MomentumFlow::rate_rise(double mu_stop, double i0, double h_m, double speed_m_s) const {
  if (!(speed_m_s > 0.0)) return mu_stop;
  if (!(h_m > 0.0)) return std::max(mu_stop, rate_mu_);
  const double inertial = speed_m_s * rate_grain_m_ / (h_m * std::sqrt(kGravity_m_s2 * h_m));
  return mu_stop + std::max(0.0, rate_mu_ - mu_stop) * inertial / (i0 + inertial);
}

MomentumFlow::MomentumFlow(const GranularGrid& grid, const MomentumFlowParameters& params, double step_dt_s)
    : step_dt_s_(step_dt_s),
      d_(grid.cell_size_m()),
      courant_(params.courant),
      max_substeps_(params.max_substeps),
      gather_steps_(params.gather_steps),
      raining_(params.raining),
      erosion_(params.erosion),
      owns_cells_(params.owns_cells),
      taper_feed_(params.front_feed == MomentumFlowParameters::FrontFeed::kTaper),
      deposition_(params.deposition),
      laid_down_holds_(params.laid_down_holds),
      layer_depth_(params.layer_depth) {
  const SoilFlowParameters& soil = grid.soil();
  const double bed_deg = params.bed_friction_deg > 0.0 ? params.bed_friction_deg : soil.flowing_friction_deg();
  const double start_deg = params.start_friction_deg > 0.0 ? params.start_friction_deg : soil.repose_angle_deg;
  if (!(bed_deg > 0.0 && bed_deg < 89.0 && start_deg >= bed_deg && start_deg < 89.0))
    throw std::invalid_argument("momentum flow: bed friction must be in (0, 89) deg and at most the start friction");
  if (!(courant_ > 0.0 && (courant_ <= kCourantBound || (params.study_past_bound && courant_ <= 8.0))))
    throw std::invalid_argument("momentum flow: courant must be in (0, 0.5] (up to 8 in a study past the bound)");
  mu_ = tan_deg(bed_deg);
  if (!(params.floor_friction_deg >= 0.0 && params.floor_friction_deg < 89.0))
    throw std::invalid_argument("momentum flow: floor_friction_deg must be in [0, 89)");
  floor_mu_ = params.floor_friction_deg > 0.0 ? tan_deg(params.floor_friction_deg) : -1.0;  // < 0: the bed's
  if (!(params.grain_diameter_m >= 0.0 && params.grain_diameter_m <= 10.0))
    throw std::invalid_argument("momentum flow: grain_diameter_m must be in [0, 10]");
  const double grain_m = params.grain_diameter_m > 0.0 ? params.grain_diameter_m : soil.grain_diameter_m;
  // h_stop, the thinnest layer that flows, is a grain-scale length like the
  // thin-layer law's: grains scaled with the other lengths (a dimensionless
  // comparison) scale it with them.
  min_layer_m_ = soil.min_flow_layer_m * (soil.grain_diameter_m > 0.0 && grain_m > 0.0 ? grain_m / soil.grain_diameter_m : 1.0);
  if (grain_m > 0.0 && soil.thin_layer_decay_grains > 0.0) {
    thin_excess_ = std::max(0.0, tan_deg(soil.thin_layer_friction_angle_deg) - mu_);
    inv_decay_m_ = 1.0 / (soil.thin_layer_decay_grains * grain_m);
  }
  if (params.rate_friction) {
    if (!(soil.rate_friction_angle_deg > 0.0 && soil.rate_friction_i0 > 0.0 && grain_m > 0.0))
      throw std::invalid_argument(
          "momentum flow: rate_friction needs the soil's rate_friction_angle_deg, rate_friction_i0 (> 0) and grain diameter");
    rate_mu_ = tan_deg(soil.rate_friction_angle_deg);
    rate_i0_ = soil.rate_friction_i0;
    rate_grain_m_ = grain_m;
  }
  if (!(params.floor_rate_friction_i0 >= 0.0 && params.floor_rate_friction_i0 <= 10.0))
    throw std::invalid_argument("momentum flow: floor_rate_friction_i0 must be in [0, 10]");
  floor_rate_i0_ = params.floor_rate_friction_i0;
  if (params.side_wall_gap_m > 0.0) {
    if (!(params.side_wall_friction_deg >= 0.0 && params.side_wall_friction_deg < 89.0))
      throw std::invalid_argument("momentum flow: side_wall_friction_deg must be in [0, 89)");
    wall_mu_over_gap_ = tan_deg(params.side_wall_friction_deg) / params.side_wall_gap_m;
  }
  mu_start_ = tan_deg(start_deg);
  // The soil's bed start angle (terrain/flow_law.h; docs/fast_flows.md):
  // 0, none, and every bed under a moving layer erodes to the bed friction.
  const double bed_start_deg = soil.bed_start_angle_deg;
  if (!(bed_start_deg == 0.0 || (bed_start_deg >= bed_deg && bed_start_deg <= start_deg)))
    throw std::invalid_argument("momentum flow: the soil's bed_start_angle_deg must be 0 or between the bed friction and the "
                                "start friction");
  bed_start_tan_ = bed_start_deg > 0.0 ? tan_deg(bed_start_deg) : 0.0;
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
  nx_ = grid.nx(), ny_ = grid.ny();
  const std::size_t n = static_cast<std::size_t>(nx_) * ny_;
  const std::size_t nxf = static_cast<std::size_t>(nx_ + 1) * ny_, nyf = static_cast<std::size_t>(nx_) * (ny_ + 1);
  ux_face_.assign(nxf, 0.0);
  uy_face_.assign(nyf, 0.0);
  x_sent_.assign(nxf, 0);
  y_sent_.assign(nyf, 0);
  x_listed_.assign(nxf, 0);
  y_listed_.assign(nyf, 0);
  listed_.assign(n, 0);
  flowing_.assign(n, 0);
  core_.assign(n, 0.0);
  rain_.assign(n, 0);
  rain_speed_.assign(n, 0.0);
  fell_.assign(n, 0);
  event_bed_m_.assign(n, std::numeric_limits<double>::quiet_NaN());
  if (taper_feed_) {
    fed_path_.reserve(n);
    fed_stamp_.assign(n, 0u);
    fed_memo_.assign(n, 0);
  }
  impact_c_ = soil.impact_sheet_speed_ratio;
  impact_min_sheet2_m2_s2_ = 2.0 * mu_ * kGravity_m_s2 * d_;
  if (impact_c_ > 0.0) {
    landed_m2_s_.assign(n, 0.0);
    landed_m_.assign(n, 0.0);
    impact_pressure_.assign(n, 0.0);
    impact_sheet_m_s_.assign(n, 0.0);
    impact_reach_.assign(n, 1.0);
    impacted_.reserve(n);
    impact_depth_.assign(n, 0);
    impact_scratch_.reserve(2 * n);
  }
  in_event_.reserve(n);  // a long event may reach every cell
}

std::array<int, 4> MomentumFlow::faces_of(int cell) const {
  const int i = cell % nx_, j = cell / nx_;
  return {x_face(i + 1, j), x_face(i, j), y_face(i, j + 1), y_face(i, j)};
}

std::pair<int, int> MomentumFlow::sides(const GranularGrid& grid, int face, bool x) const {
  return x ? sides_at(grid, face % (nx_ + 1), face / (nx_ + 1), true) : sides_at(grid, face % nx_, face / nx_, false);
}

[[gnu::always_inline]] inline std::pair<int, int> MomentumFlow::sides_at(const GranularGrid& grid, int i, int j, bool x) const {
  const auto open = [&](int c) { return grid.covered(c) ? -2 : c; };
  if (x) {
    if (i > 0 && i < nx_) return {open(j * nx_ + i - 1), open(j * nx_ + i)};  // inside the grid
    return {cell_or_edge(grid, i - 1, j, kEdgeXMin), cell_or_edge(grid, i, j, kEdgeXMax)};
  }
  if (j > 0 && j < ny_) return {open((j - 1) * nx_ + i), open(j * nx_ + i)};
  return {cell_or_edge(grid, i, j - 1, kEdgeYMin), cell_or_edge(grid, i, j, kEdgeYMax)};
}

void MomentumFlow::reserve_cells(std::size_t cells) {
  cells = std::min(cells, flowing_.size());
  candidates_.reserve(cells), moving_.reserve(cells), rise_.reserve(cells), layer_.reserve(cells), keep_.reserve(cells);
  bed_floor_m_.reserve(cells);
  if (owns_cells_) slowed_from_.reserve(cells), slowed_to_.reserve(cells), held_.reserve(cells);
  x_faces_.reserve(2 * cells), y_faces_.reserve(2 * cells), new_x_.reserve(2 * cells), new_y_.reserve(2 * cells);
  new_flowing_.reserve(8 * cells);
}

void MomentumFlow::mark(int cell) {
  if (listed_[cell]) return;
  listed_[cell] = 1;
  candidates_.push_back(cell);
}

void MomentumFlow::mark_face(int face, bool x) {
  std::vector<std::uint8_t>& listed = x ? x_listed_ : y_listed_;
  if (listed[face]) return;
  listed[face] = 1;
  (x ? x_faces_ : y_faces_).push_back(face);
}

void MomentumFlow::wake_all(const GranularGrid& grid) {
  for (int c = 0; c < grid.nx() * grid.ny(); ++c)
    if (grid.loose_quanta(c) > 0) mark(c);
  woken_all_ = true;  // (the next step moves them, gathering or not)
}

double MomentumFlow::velocity_x_m_s(int cell) const {
  const std::array<int, 4> f = faces_of(cell);
  return 0.5 * (ux_face_[f[1]] + ux_face_[f[0]]);
}
double MomentumFlow::velocity_y_m_s(int cell) const {
  const std::array<int, 4> f = faces_of(cell);
  return 0.5 * (uy_face_[f[3]] + uy_face_[f[2]]);
}
double MomentumFlow::speed_m_s(int cell) const { return std::hypot(velocity_x_m_s(cell), velocity_y_m_s(cell)); }

double MomentumFlow::cross_speed_at_x_face(int i, int j) const {
  // The y-faces of cells (i - 1, j) and (i, j).
  double sum = 0.0;
  int n = 0;
  for (int ci : {i - 1, i})
    if (ci >= 0 && ci < nx_) sum += uy_face_[y_face(ci, j)] + uy_face_[y_face(ci, j + 1)], n += 2;
  return n > 0 ? sum / n : 0.0;
}
double MomentumFlow::cross_speed_at_y_face(int i, int j) const {
  double sum = 0.0;
  int n = 0;
  for (int cj : {j - 1, j})
    if (cj >= 0 && cj < ny_) sum += ux_face_[x_face(i, cj)] + ux_face_[x_face(i + 1, cj)], n += 2;
  return n > 0 ? sum / n : 0.0;
}

void MomentumFlow::step(GranularGrid& grid) {
  last_substeps_ = 0;
  // At rest: nothing to do (a landing's pressure still relaxing keeps the
  // flow stepping until it ends).
  if (at_rest()) {
    gathered_s_ = 0.0;
    return;
  }
  // Sub-steps for the fastest signal among the moving cells and the
  // candidates (Courant number courant_), within the bound checked at
  // construction: a moving cell's gravity wave runs in its flowing layer
  // (and the rain landing on it) over a static bed, sqrt(g K f); a cell
  // woken from outside (wake_all, land) may fail down to its whole loose
  // depth.
  double fastest = 0.0;
  auto signal = [&](int c, bool woken) {
    const double h = (woken ? grid.loose_quanta(c) : flowing_[c] + rain_[c]) * kHeightQuantumM;
    const std::array<int, 4> f = faces_of(c);
    const double u = std::max(std::abs(ux_face_[f[1]]), std::abs(ux_face_[f[0]]));
    const double v = std::max(std::abs(uy_face_[f[3]]), std::abs(uy_face_[f[2]]));
    // (a landing's sheet: up to c V)
    return u + v + std::sqrt(kGravity_m_s2 * k_passive_ * h) + (impacted_.empty() ? 0.0 : impact_sheet_m_s_[c]);
  };
  if (!impacted_.empty()) {
    shape_impacts();
    ++pressed_steps_;
  }
  for (int c : moving_) fastest = std::max(fastest, signal(c, false));
  for (int c : candidates_) fastest = std::max(fastest, signal(c, true));
  gathered_s_ += step_dt_s_;
  // Gathering steps (docs/fast_flows.md, "Gathering steps"): a flow that
  // the next step would still leave within one sub-step's Courant number
  // waits for it, and then moves the time gathered in one sub-step; not
  // under a landing's pressure (it relaxes step by step) nor with the
  // cells of wake_all still to fail. A layer may also gain speed over the
  // span, at up to about g (set moving beside a failure, speeding down a
  // slope): g T^2 stays within what the bound leaves over the sub-steps'
  // Courant number, so (fastest + g T) T <= kCourantBound d.
  const double span_next_s = gathered_s_ + step_dt_s_;
  if (gather_steps_ && impacted_.empty() && !woken_all_ && fastest * span_next_s <= courant_ * d_ &&
      kGravity_m_s2 * span_next_s * span_next_s <= (kCourantBound - courant_) * d_)
    return;
  const double span_s = gathered_s_;
  gathered_s_ = 0.0;
  woken_all_ = false;
  const int n = std::clamp(static_cast<int>(std::ceil(fastest * span_s / (courant_ * d_) - 1e-12)), 1, max_substeps_);
  for (int s = 0; s < n && !(moving_.empty() && candidates_.empty()); ++s) {
    substep(grid, span_s / n);
    ++last_substeps_;
    ++substeps_run_;
  }
  for (int c : impacted_) impact_depth_[c] = 0, landed_m2_s_[c] = 0.0, impact_reach_[c] = 1.0;  // (the shaped pressure) ready for the next landings
  if (owns_cells_) hold_flowing_cells(grid);
}

void MomentumFlow::hold_flowing_cells(GranularGrid& grid) {
  // A cell with a flowing layer is a moving cell (settle); one that lost its
  // layer goes back to the automaton, the others stay held.
  std::size_t kept = 0;
  for (int c : held_) {
    if (flowing_[c] > 0) held_[kept++] = c;
    else grid.set_held(c, false);
  }
  held_.resize(kept);
  for (int c : moving_)
    if (flowing_[c] > 0 && !grid.held(c)) grid.set_held(c, true), held_.push_back(c);
}

void MomentumFlow::lay_down_slowed() {
  // A layer of linear profile over its flowing depth h_f (mean speed
  // gamma_dot h_f / 2) whose lowest grains come to rest first, under the
  // grains still running (the DEM's collapses and stopping layers:
  // dem/collapse/results*/profile_*.csv, dem/calibration/results/stopping_*.csv),
  // slowed from u0 to u (its centre's speed). What it lays down is bed, the
  // cell's static soil (no material moves, so the books stay exact).
  //   The interface (Lusso et al. 2017): the forces slow every depth alike
  // by a dt, so the speed reaches zero a dt / gamma_dot higher and the
  // grains there stop with next to no speed: the layer keeps its momentum,
  // its thickness h_f' and mean speed u' with h_f' / h_f = u' / u0 (the
  // profile kept) and h_f' u' = h_f u, hence h_f' = h_f sqrt(u / u0) and
  // u' = sqrt(u0 u). Every speed is read before any face is scaled (each
  // face by its donor's factor h_f / h_f'), so the cells' order does not
  // matter.
  //   The mean speed's rule: it keeps u / u0 of its thickness and the faces
  // their speeds, the grains laid down taking the mean speed's share of the
  // momentum.
  const bool interface = deposition_ == MomentumFlowParameters::Deposition::kInterface;
  if (interface) slowed_to_.assign(candidates_.size(), 1.0);
  for (std::size_t n = 0; n < candidates_.size(); ++n) {
    const int c = candidates_[n];
    if (flowing_[c] <= 0 || rain_[c] > 0) continue;
    const double before = slowed_from_[n], after = speed_m_s(c);
    if (!(before > 0.0) || after >= before) continue;
    const double h = static_cast<double>(flowing_[c]);
    const std::int64_t kept = interface ? static_cast<std::int64_t>(h * std::sqrt(after / before))
                                        : flowing_[c] - static_cast<std::int64_t>(h * (before - after) / before);
    if (kept == flowing_[c]) continue;
    if (interface && kept > 0) slowed_to_[n] = h / static_cast<double>(kept);
    // What it lays down joins the bed its event found (a NaN found bed: the
    // soil has no bed start angle).
    if (laid_down_holds_ && !std::isnan(event_bed_m_[c]))
      event_bed_m_[c] += static_cast<double>(flowing_[c] - kept) * kHeightQuantumM;
    flowing_[c] = kept;  // (none kept: the layer has lain down, and settle stops its faces)
  }
  if (!interface) return;
  for (std::size_t n = 0; n < candidates_.size(); ++n) {
    if (slowed_to_[n] == 1.0) continue;
    const std::array<int, 4> faces = faces_of(candidates_[n]);
    for (int k = 0; k < 4; ++k)
      if (leaves(k, face_u(k, faces[k]))) face_u(k, faces[k]) *= slowed_to_[n];
  }
}

void MomentumFlow::substep(GranularGrid& grid, double dt_s) {
  // The cells to examine: the moving ones, their neighbours and the woken
  // ones; the faces: every face of those.
  for (int c : moving_) {
    mark(c);
    const int i = c % nx_, j = c / nx_;
    for (int k = 0; k < 4; ++k) {
      const int nb = neighbour(grid, i, j, k);
      if (nb >= 0) mark(nb);
    }
  }
  raster_order_candidates();
  for (int c : candidates_) {
    const std::array<int, 4> f = faces_of(c);
    mark_face(f[1], true), mark_face(f[0], true);
    mark_face(f[3], false), mark_face(f[2], false);
  }
  fail(grid, dt_s);
  if (owns_cells_) {
    slowed_from_.resize(candidates_.size());
    for (std::size_t n = 0; n < candidates_.size(); ++n) slowed_from_[n] = speed_m_s(candidates_[n]);
  }
  accelerate(grid, dt_s);
  // The interface follows the forces' slowing, not the mixing with what
  // arrives (which brings momentum, not friction); the mean speed's rule,
  // as first written, reads both.
  const bool interface = owns_cells_ && deposition_ == MomentumFlowParameters::Deposition::kInterface;
  if (interface) lay_down_slowed();
  transport(grid, dt_s);
  carry_momentum(grid);
  if (owns_cells_ && !interface) lay_down_slowed();
  settle(grid);
  // The flow at rest: its event is over, and what it laid down is bed at
  // rest like the rest.
  if (moving_.empty()) {
    for (int c : in_event_) event_bed_m_[c] = std::numeric_limits<double>::quiet_NaN();
    in_event_.clear();
  }
  for (int c : candidates_) listed_[c] = 0;
  for (int f : x_faces_) x_listed_[f] = 0, x_sent_[f] = 0;
  for (int f : y_faces_) y_listed_[f] = 0, y_sent_[f] = 0;
  candidates_.clear(), x_faces_.clear(), y_faces_.clear();
}

void MomentumFlow::accelerate(const GranularGrid& grid, double dt_s) {
  // Each face's velocity from the surfaces on its two sides (a peak pushes
  // out across every face), the earth pressure of the flowing layers, and
  // Coulomb friction on the bed (and the side walls) along the flow's
  // direction; a face whose donor holds no flowing layer stands still.
  // Every face is read before any is written.
  // The divergence of cell (ci, cj)'s faces.
  auto divergence = [&](int ci, int cj) {
    return ux_face_[x_face(ci + 1, cj)] - ux_face_[x_face(ci, cj)] + uy_face_[y_face(ci, cj + 1)] - uy_face_[y_face(ci, cj)];
  };
  // Face (i, j) along x or y, with velocity u.
  auto face_velocity = [&](bool x, int i, int j, double u) {
    // a, b: the cells on the face's minus and plus sides (-1 drop-off, -2 wall).
    const auto [a, b] = sides_at(grid, i, j, x);
    if (a == -2 || b == -2) return 0.0;
    if (u == 0.0 && (a < 0 || flowing_[a] == 0) && (b < 0 || flowing_[b] == 0)) return 0.0;  // nothing to move
    const double ha = a >= 0 ? grid.surface_at(a) - rain_[a] * kHeightQuantumM : grid.base_at(b);
    const double hb = b >= 0 ? grid.surface_at(b) - rain_[b] * kHeightQuantumM : grid.base_at(a);
    const double fa = a >= 0 ? flowing_[a] * kHeightQuantumM : 0.0, fb = b >= 0 ? flowing_[b] * kHeightQuantumM : 0.0;
    // The landings' pressure (land, shape_impacts): -grad(p) / rho over
    // the sub-step. It speeds a face up to the stagnation flow's speed
    // c V r / R at most (the ideal flow under p's profile has V r / R; V
    // the landing's mean fall speed, r / R the mean of the face's two
    // cells', 1 outside the footprint): c is what the grains' collisions
    // leave of the fall (the DEM's jet), and without a bound the face's
    // velocity, pushed step after step, would grow without end.
    double kick = 0.0, sheet = 0.0;
    if (!impacted_.empty()) {
      const double pa = a >= 0 ? landed_m2_s_[a] : 0.0, pb = b >= 0 ? landed_m2_s_[b] : 0.0;
      kick = -(pb - pa) / d_ * dt_s;
      if (kick != 0.0) {  // (a face outside every footprint, or across its middle, feels none)
        if (a >= 0) sheet = std::max(sheet, impact_sheet_m_s_[a]);
        if (b >= 0) sheet = std::max(sheet, impact_sheet_m_s_[b]);
        sheet *= 0.5 * ((a >= 0 ? impact_reach_[a] : 1.0) + (b >= 0 ? impact_reach_[b] : 1.0));
      }
    }
    // The donor is the side the face's flow would come from.
    const double push = -kGravity_m_s2 * (hb - ha) / d_ * dt_s + kick;
    const bool plus = u != 0.0 ? u > 0.0 : push > 0.0;
    const int donor = plus ? a : b;
    if (donor < 0 || flowing_[donor] == 0) return 0.0;
    // Savage-Hutter's K switches with the donor's divergence (spreading:
    // active); one K (the default, 1) needs no divergence.
    const double k_earth = k_active_ == k_passive_ ? k_active_
                           : (plus ? divergence(x ? i - 1 : i, x ? j : j - 1) : divergence(i, j)) >= 0.0 ? k_active_ : k_passive_;
    // -g (grad H + (K - 1) grad f): Savage-Hutter (2.23) on the face.
    const double acc = -kGravity_m_s2 * ((hb - ha) + (k_earth - 1.0) * (fb - fa)) / d_;
    double un = u + acc * dt_s;
    if (kick != 0.0) un = std::abs(un) >= sheet ? un : std::clamp(un + kick, -sheet, sheet);
    const double cross = x ? cross_speed_at_x_face(i, j) : cross_speed_at_y_face(i, j);
    const double f = flowing_[donor] * kHeightQuantumM;
    // A layer with no static soil under it rubs on the hard base; on soil,
    // the thin-layer law reads the depth the layer moves in, and so do the
    // side walls (Jop et al. 2005: the walls' pressure over that depth).
    const double depth_m = thin_excess_ > 0.0 || wall_mu_over_gap_ > 0.0 || rate_mu_ > 0.0 ? layer_depth_m(grid, donor, f) : f;
    const double speed = std::sqrt(un * un + cross * cross);
    const double mu = on_floor(grid, donor, flowing_[donor]) ? floor_friction_tan(f, speed) : bed_friction_tan(depth_m, speed);
    const double loss = (mu + wall_mu_over_gap_ * depth_m) * kGravity_m_s2 * dt_s;
    return speed > loss ? un * (speed - loss) / speed : 0.0;
  };
  new_x_.resize(x_faces_.size());
  new_y_.resize(y_faces_.size());
  for (std::size_t n = 0; n < x_faces_.size(); ++n) {
    const int f = x_faces_[n];
    new_x_[n] = face_velocity(true, f % (nx_ + 1), f / (nx_ + 1), ux_face_[f]);
  }
  for (std::size_t n = 0; n < y_faces_.size(); ++n) {
    const int f = y_faces_[n];
    new_y_[n] = face_velocity(false, f % nx_, f / nx_, uy_face_[f]);
  }
  for (std::size_t n = 0; n < x_faces_.size(); ++n) ux_face_[x_faces_[n]] = new_x_[n];
  for (std::size_t n = 0; n < y_faces_.size(); ++n) uy_face_[y_faces_[n]] = new_y_[n];
}

void MomentumFlow::transport(GranularGrid& grid, double dt_s) {
  // A flowing layer sends f_face |u| dt / d across each face whose velocity
  // leaves it, rounded to quanta, all from the state before the sub-step
  // (scaled down, exactly within f, only past the Courant bound).
  new_flowing_.clear();
  for (int c : candidates_) {
    const std::int64_t q = flowing_[c];
    if (q == 0) continue;
    const int i = c % nx_, j = c / nx_;
    const std::array<int, 4> faces = faces_of(c);
    const double u[4] = {std::max(ux_face_[faces[0]], 0.0), std::max(-ux_face_[faces[1]], 0.0),
                         std::max(uy_face_[faces[2]], 0.0), std::max(-uy_face_[faces[3]], 0.0)};
    if (!(u[0] > 0.0 || u[1] > 0.0 || u[2] > 0.0 || u[3] > 0.0)) continue;
    const int nb[4] = {neighbour(grid, i, j, 0), neighbour(grid, i, j, 1), neighbour(grid, i, j, 2), neighbour(grid, i, j, 3)};
    std::int64_t out[4] = {0, 0, 0, 0}, total = 0;
    for (int k = 0; k < 4; ++k) {
      if (!(u[k] > 0.0)) continue;
      // f_face: the donor's layer corrected by half its minmod slope along
      // the flow times (1 - Courant), a flux-limited Lax-Wendroff flux
      // (LeVeque 2002, (6.39)): TVD up to Courant 1, so it adds no extrema,
      // and at most 1.5 f. Donor cell (f_face = f) let a front run ahead of
      // itself by a cell's smear each step.
      const int down = nb[k], up = nb[k ^ 1];
      const double here = static_cast<double>(q), courant = u[k] * dt_s / d_;
      const double behind = up >= 0 ? here - static_cast<double>(flowing_[up]) : 0.0;
      const double ahead = down >= 0 ? static_cast<double>(flowing_[down]) - here : -here;
      const double slope = behind * ahead <= 0.0 ? 0.0 : (std::abs(behind) < std::abs(ahead) ? behind : ahead);
      const double at_face = here + 0.5 * (1.0 - courant) * slope;
      total += out[k] = std::llround(at_face * courant);
    }
    if (total > q)
      for (int k = 0; k < 4; ++k) out[k] = out[k] * q / total;
    for (int k = 0; k < 4; ++k) {
      if (out[k] == 0) continue;
      if (nb[k] == -2) continue;  // a face into a wall stands still (accelerate)
      grid.transfer_quanta(c, nb[k], out[k], kEdgeOf[k]);
      (k < 2 ? x_sent_ : y_sent_)[faces[k]] += k % 2 == 0 ? out[k] : -out[k];
      new_flowing_.emplace_back(c, -out[k]);
      if (nb[k] >= 0) new_flowing_.emplace_back(nb[k], out[k]);
    }
  }
  for (const auto& [c, dq] : new_flowing_) flowing_[c] += dq;
}

[[gnu::always_inline]] inline MomentumFlow::Arrival MomentumFlow::arrival(int i, int j, bool x, bool plus_side) const {
  // Face (i, j)'s donor on the given side is cell (ci, cj). What arrived
  // there across its face along the same axis carries that face's velocity;
  // what arrived across its two cross faces carries the velocity of the
  // face parallel to this one in the row it came from (j -+ 1 for an x-face,
  // i -+ 1 for a y-face): a layer moving diagonally keeps both components.
  Arrival out;
  auto add = [&](std::int64_t in, double u) {
    if (in <= 0) return;
    out.quanta += static_cast<double>(in);
    out.momentum += static_cast<double>(in) * u;
  };
  if (x) {
    const int ci = plus_side ? i : i - 1, cj = j;
    if (ci < 0 || ci >= nx_) return out;
    const int along = plus_side ? x_face(i + 1, j) : x_face(i - 1, j);
    add(plus_side ? -x_sent_[along] : x_sent_[along], ux_face_[along]);
    if (cj > 0) add(y_sent_[y_face(ci, cj)], ux_face_[x_face(i, cj - 1)]);
    if (cj + 1 < ny_) add(-y_sent_[y_face(ci, cj + 1)], ux_face_[x_face(i, cj + 1)]);
  } else {
    const int ci = i, cj = plus_side ? j : j - 1;
    if (cj < 0 || cj >= ny_) return out;
    const int along = plus_side ? y_face(i, j + 1) : y_face(i, j - 1);
    add(plus_side ? -y_sent_[along] : y_sent_[along], uy_face_[along]);
    if (ci > 0) add(x_sent_[x_face(ci, cj)], uy_face_[y_face(ci - 1, j)]);
    if (ci + 1 < nx_) add(-x_sent_[x_face(ci + 1, cj)], uy_face_[y_face(ci + 1, j)]);
  }
  return out;
}

void MomentumFlow::carry_momentum(const GranularGrid& grid) {
  // Momentum goes with the material (Stelling and Duinmeijer 2003's
  // momentum-conserving upwind form, with its cross terms): a face's
  // velocity is that of its donor's flowing layer, which is what stayed
  // there at the face's velocity mixed, by mass, with what arrived there
  // this sub-step (arrival). A face standing still takes the velocity of
  // what arrived at either of its cells moving towards it (a front
  // advancing into a bare cell, along an axis or a diagonal), so the
  // material that advances keeps its momentum; material arriving from both
  // sides at once leaves it standing, and nothing moves into a wall.
  auto mixed = [&](double u, int donor, const Arrival& in) {
    if (donor < 0 || flowing_[donor] <= 0 || in.quanta <= 0.0) return u;
    const double w = std::min(1.0, in.quanta / static_cast<double>(flowing_[donor]));
    return (1.0 - w) * u + w * (in.momentum / in.quanta);
  };
  auto carried = [&](bool x, int face, double u) {
    const int n = x ? nx_ + 1 : nx_, i = face % n, j = face / n;
    const auto [a, b] = sides_at(grid, i, j, x);
    if (u > 0.0) return mixed(u, a, arrival(i, j, x, false));
    if (u < 0.0) return mixed(u, b, arrival(i, j, x, true));
    if (a == -2 || b == -2) return u;
    const Arrival from_a = arrival(i, j, x, false), from_b = arrival(i, j, x, true);
    const bool minus = a >= 0 && from_a.momentum > 0.0, plus = b >= 0 && from_b.momentum < 0.0;
    if (minus == plus) return u;
    return minus ? mixed(u, a, from_a) : mixed(u, b, from_b);
  };
  new_x_.resize(x_faces_.size());
  new_y_.resize(y_faces_.size());
  for (std::size_t n = 0; n < x_faces_.size(); ++n) new_x_[n] = carried(true, x_faces_[n], ux_face_[x_faces_[n]]);
  for (std::size_t n = 0; n < y_faces_.size(); ++n) new_y_[n] = carried(false, y_faces_[n], uy_face_[y_faces_[n]]);
  for (std::size_t n = 0; n < x_faces_.size(); ++n) ux_face_[x_faces_[n]] = new_x_[n];
  for (std::size_t n = 0; n < y_faces_.size(); ++n) uy_face_[y_faces_[n]] = new_y_[n];
}

}  // namespace skidsim::terrain
