#include "terrain/granular_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace skidsim::terrain {
namespace {

// Neighbour order used everywhere: +x, -x, +y, -y. The edge a neighbour
// direction crosses when it leaves the grid:
constexpr Edge kEdgeOfDirection[4] = {kEdgeXMax, kEdgeXMin, kEdgeYMax, kEdgeYMin};

// Per-cell bits saying which grid edges the cell touches, so that the sweep
// needs no division to find them. Stored in the upper bits of flags.
constexpr std::uint8_t kOnEdgeBit[4] = {16, 8, 64, 32};  // indexed by direction
constexpr std::uint8_t kOnAnyEdge = 16 | 8 | 64 | 32;

__extension__ typedef __int128 Int128;  // exact product of two quanta counts

std::int64_t to_quanta(double height_m) {
  return static_cast<std::int64_t>(std::llround(height_m / kHeightQuantumM));
}

// SplitMix64: a small, fully specified generator, so a shuffled sweep order
// is the same on every platform.
std::uint64_t split_mix(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// (4.16) as a finite-volume flux through one face: if the face is downhill
// and its slope tan(beta) exceeds the threshold, the normal component
// (drop/d)/tan(beta) of the flux z+(beta) (tan beta - tan alpha_I) along the
// gradient, with the transport floor of h_stop; in quanta, plus 0.5 for the
// rounding; zero otherwise. Each face flux is at most z+ drop / d, which is
// what the stability bound rests on. Branch-free, so that loops over faces
// vectorise; every sweep uses this one function, so the sparse and dense
// sweeps are bit-identical.
inline double face_flux_quanta(double drop_m, double tangential_m, double inv_d, double threshold2,
                               const FlowLaw& law) {
  const double normal = drop_m * inv_d, tangential = tangential_m * inv_d;
  const double tan2 = normal * normal + tangential * tangential;
  const double tan_beta = std::sqrt(tan2);
  // One face carries at most 2 m per sweep; a higher cliff just takes more
  // sweeps (a smaller flux keeps the bound).
  const double quanta = std::min(law.moved_height_m(tan_beta) * (normal / tan_beta) * (1.0 / kHeightQuantumM), 2.0e9);
  const bool flows = (drop_m > 0.0) & (tan2 > threshold2);
  return flows ? quanta + 0.5 : 0.0;
}

}  // namespace

GranularGrid::GranularGrid(const GridSpec& spec, const SoilFlowParameters& soil,
                           double step_dt_s, int max_substeps)
    : spec_(spec), soil_(soil) {
  if (spec.nx < 1 || spec.ny < 1) {
    std::ostringstream msg;
    msg << "grid size " << spec.nx << " x " << spec.ny << " cells: both must be >= 1";
    throw std::invalid_argument(msg.str());
  }
  if (static_cast<std::int64_t>(spec.nx) * spec.ny > std::numeric_limits<std::int32_t>::max())
    throw std::invalid_argument("grid has more than 2^31 cells");
  if (!(spec.flow_bound_fraction > 0.0 && spec.flow_bound_fraction <= 1.0))
    throw std::invalid_argument("grid flow_bound_fraction must be in (0, 1]");
  const bool slippage = soil.model == GroundModel::kSlippage;
  law_ = derive_flow_law(soil, spec.cell_size_m, step_dt_s, slippage ? std::numeric_limits<int>::max() : max_substeps,
                         spec.flow_bound_fraction);
  const std::size_t n = static_cast<std::size_t>(spec.nx) * spec.ny;
  if (slippage) {
    slip_ = derive_slippage_law(soil, spec.cell_size_m, step_dt_s, max_substeps, spec.flow_bound_fraction,
                                spec.slide_courant_limit, spec.slide_beyond_bound_for_study);
    // The grid sweeps at the slippage model's sub-steps. The automaton's law
    // stays for what bodies exchange per step (material over a bucket's
    // lip, 6.3, material_exchange.cpp): its z+ per sweep is rescaled so
    // that z+ per step is unchanged.
    law_.z_plus_per_sweep_m *= static_cast<double>(law_.substeps) / slip_.substeps;
    law_.substeps = slip_.substeps;
    law_.sweep_dt_s = slip_.sweep_dt_s;
    slide_speed_.assign(n, 0.0f);
    loose_.assign(n, 0);
  }
  quanta_.assign(n, 0);
  base_m_.assign(n, 0.0f);
  surface_m_.assign(n, 0.0);
  flags_.assign(n, 0);
  for (int j = 0; j < spec.ny; ++j) {
    for (int i = 0; i < spec.nx; ++i) {
      std::uint8_t bits = 0;
      if (i == spec.nx - 1) bits |= kOnEdgeBit[0];
      if (i == 0) bits |= kOnEdgeBit[1];
      if (j == spec.ny - 1) bits |= kOnEdgeBit[2];
      if (j == 0) bits |= kOnEdgeBit[3];
      flags_[index(i, j)] = bits;
    }
  }
}

std::int64_t GranularGrid::total_quanta() const {
  std::int64_t total = 0;
  for (std::int64_t q : quanta_) total += q;
  for (std::int64_t q : compacted_) total += q;
  return total;
}

void GranularGrid::set_covered(int cell, bool covered) {
  const bool was = (flags_[cell] & kCovered) != 0;
  if (was == covered) return;
  flags_[cell] = static_cast<std::uint8_t>(covered ? (flags_[cell] | kCovered) : (flags_[cell] & ~kCovered));
  covered_count_ += covered ? 1 : -1;
  wake(cell);
}

void GranularGrid::set_held(int cell, bool held) {
  if (held_.empty()) {
    if (!held) return;
    held_.assign(quanta_.size(), 0);
  }
  if ((held_[cell] != 0) == held) return;
  held_[cell] = held ? 1 : 0;
  held_count_ += held ? 1 : -1;
  wake(cell);
}

std::int64_t GranularGrid::compact_quanta(int cell, std::int64_t quanta) {
  const std::int64_t q = std::max<std::int64_t>(0, std::min(quanta, quanta_[cell]));
  if (q == 0) return 0;
  if (compacted_.empty()) compacted_.assign(quanta_.size(), 0);
  quanta_[cell] -= q;
  take_from_top(cell, q);
  compacted_[cell] += q;
  refresh_surface(cell);
  wake(cell);
  return q;
}

std::int64_t GranularGrid::transfer_quanta(int from, int to, std::int64_t quanta, Edge edge) {
  const std::int64_t q = std::max<std::int64_t>(0, std::min(quanta, quanta_[from]));
  if (q == 0) return 0;
  quanta_[from] -= q;
  take_from_top(from, q);
  refresh_surface(from);
  wake(from);
  if (to >= 0) {
    quanta_[to] += q;
    loosen(to, q);
    flags_[to] |= kFlowing;  // pushed material arrives moving (4.5)
    refresh_surface(to);
    wake(to);
  } else {
    ledger_.off_site[edge] += q;
  }
  return q;
}

void GranularGrid::block_covered_faces(std::uint32_t cell, FaceGeometry& g) const {
  if (covered_count_ == 0) return;
  const std::uint8_t f = flags_[cell];
  if (f & kCovered) {
    for (double& d : g.drop) d = 0.0;
    return;
  }
  const int offset[4] = {1, -1, spec_.nx, -spec_.nx};
  for (int d = 0; d < 4; ++d)
    if (!(f & kOnEdgeBit[d]) && (flags_[cell + offset[d]] & kCovered)) g.drop[d] = 0.0;
}

MaterialLedger GranularGrid::ledger() const {
  MaterialLedger out = ledger_;
  out.in_cells = total_quanta();
  return out;
}

void GranularGrid::reserve_active_cells(std::size_t cells) {
  cells = std::min(cells, quanta_.size());
  pending_.reserve(cells);
  current_.reserve(cells);
  changed_.reserve(cells);
  flux_.reserve(cells);
}

std::size_t GranularGrid::scratch_bytes() const {
  return pending_.capacity() * sizeof(std::uint32_t) + current_.capacity() * sizeof(std::uint32_t) +
         changed_.capacity() * sizeof(std::uint32_t) + flux_.capacity() * sizeof(CellFlux) +
         dense_rows_.capacity() * sizeof(dense_rows_[0]) + row_q_.capacity() * sizeof(double);
}

void GranularGrid::wake_block(int cell) {
  // The 3 x 3 block: a cell's face slopes read its diagonal neighbours too.
  const std::uint8_t f = flags_[cell];
  flags_[cell] = static_cast<std::uint8_t>(f | kBlockQueued);
  const int row_lo = (f & kOnEdgeBit[3]) ? 0 : -spec_.nx, row_hi = (f & kOnEdgeBit[2]) ? 0 : spec_.nx;
  const int col_lo = (f & kOnEdgeBit[1]) ? 0 : -1, col_hi = (f & kOnEdgeBit[0]) ? 0 : 1;
  for (int row = row_lo; row <= row_hi; row += spec_.nx) {
    for (int col = col_lo; col <= col_hi; ++col) {
      const int c = cell + row + col;
      if (!(flags_[c] & kQueued)) {
        flags_[c] |= kQueued;
        pending_.push_back(static_cast<std::uint32_t>(c));
      }
    }
  }
}

void GranularGrid::check_cell(const char* what, int i, int j) const {
  if (!contains(i, j)) {
    std::ostringstream msg;
    msg << what << ": cell (" << i << ", " << j << ") is outside the " << spec_.nx << " x " << spec_.ny << " grid";
    throw std::invalid_argument(msg.str());
  }
}

void GranularGrid::set_base_m(int i, int j, double base_m) {
  check_cell("set_base_m", i, j);
  if (!(std::abs(base_m) <= kMaxBaseAbsM)) {
    std::ostringstream msg;
    msg << "base height " << base_m << " m at cell (" << i << ", " << j << ") is not within +-" << kMaxBaseAbsM << " m";
    throw std::invalid_argument(msg.str());
  }
  base_m_[index(i, j)] = static_cast<float>(base_m);
  refresh_surface(index(i, j));
  wake(index(i, j));
}

void GranularGrid::set_material_m(int i, int j, double material_m) {
  check_cell("set_material_m", i, j);
  if (!(material_m >= 0.0 && material_m <= kMaxColumnM)) {
    std::ostringstream msg;
    msg << "material depth " << material_m << " m at cell (" << i << ", " << j << ") is not within [0, "
        << kMaxColumnM << "] m";
    throw std::invalid_argument(msg.str());
  }
  const int c = index(i, j);
  const std::int64_t q = to_quanta(material_m);
  ledger_.initial += q - quanta_[c];
  quanta_[c] = q;
  if (!loose_.empty()) loose_[c] = 0;  // the ground as it lies: intact
  refresh_surface(c);
  wake(c);
}

double GranularGrid::add_material_m3(int i, int j, double volume_m3) {
  check_cell("add_material_m3", i, j);
  const int c = index(i, j);
  const double column_after_m = material_m(i, j) + volume_m3 / (spec_.cell_size_m * spec_.cell_size_m);
  if (!(volume_m3 >= 0.0 && column_after_m <= kMaxColumnM)) {
    std::ostringstream msg;
    msg << "adding " << volume_m3 << " m^3 at cell (" << i << ", " << j << "): the volume must be >= 0 and the column"
        << " stay within " << kMaxColumnM << " m";
    throw std::invalid_argument(msg.str());
  }
  const std::int64_t q = std::llround(volume_m3 / quantum_volume_m3());
  if (q == 0) return 0.0;
  quanta_[c] += q;
  loosen(c, q);
  ledger_.added += q;
  // Poured material arrives moving: the cell flows (4.5) until it settles.
  flags_[c] |= kFlowing;
  refresh_surface(c);
  wake(c);
  return q * quantum_volume_m3();
}

double GranularGrid::remove_material_m3(int i, int j, double volume_m3) {
  check_cell("remove_material_m3", i, j);
  if (!(volume_m3 >= 0.0)) {
    std::ostringstream msg;
    msg << "removing " << volume_m3 << " m^3 at cell (" << i << ", " << j << "): the volume must be >= 0";
    throw std::invalid_argument(msg.str());
  }
  const int c = index(i, j);
  // Limited to what the cell holds (compared in double first: no overflow).
  const double wanted = volume_m3 / quantum_volume_m3();
  const std::int64_t q = wanted >= static_cast<double>(quanta_[c]) ? quanta_[c] : std::llround(wanted);
  if (q == 0) return 0.0;
  quanta_[c] -= q;
  take_from_top(c, q);
  ledger_.removed += q;
  refresh_surface(c);
  wake(c);
  return q * quantum_volume_m3();
}

GranularGrid::FaceGeometry GranularGrid::face_geometry(std::uint32_t cell) const {
  const std::uint8_t f = flags_[cell];
  const int nx = spec_.nx;
  const double* h = surface_m_.data();
  if (!(f & kOnAnyEdge)) {
    FaceGeometry g = face_geometry_from(h[cell], h[cell + 1], h[cell - 1], h[cell + nx], h[cell - nx],
                                        h[cell + 1 + nx], h[cell - 1 + nx], h[cell + 1 - nx], h[cell - 1 - nx]);
    if (tilted_) tilt_faces(g);
    block_covered_faces(cell, g);
    return g;
  }
  const double here = h[cell];
  const bool xp = !(f & kOnEdgeBit[0]), xm = !(f & kOnEdgeBit[1]);
  const bool yp = !(f & kOnEdgeBit[2]), ym = !(f & kOnEdgeBit[3]);
  // The 3 x 3 neighbourhood; outside the grid a cell repeats its neighbour
  // inside (zero gradient across the edge) for the tangential differences.
  const double e = xp ? h[cell + 1] : here, w = xm ? h[cell - 1] : here;
  const double n = yp ? h[cell + nx] : here, s = ym ? h[cell - nx] : here;
  const double ne = xp && yp ? h[cell + 1 + nx] : (xp ? e : n);
  const double nw = xm && yp ? h[cell - 1 + nx] : (xm ? w : n);
  const double se = xp && ym ? h[cell + 1 - nx] : (xp ? e : s);
  const double sw = xm && ym ? h[cell - 1 - nx] : (xm ? w : s);
  FaceGeometry g = face_geometry_from(here, e, w, n, s, ne, nw, se, sw);
  // Beyond an open edge the imaginary neighbour sits at this cell's base
  // (material falls off); a closed edge is a wall (no drop).
  for (int d = 0; d < 4; ++d) {
    if (!(f & kOnEdgeBit[d])) continue;
    double outside = base_m_[cell];
    if (capture_edges_) {
      const double neighbour = edge_neighbour_m_[static_cast<std::size_t>(
          edge_slot(static_cast<int>(cell % static_cast<std::uint32_t>(nx)), static_cast<int>(cell / static_cast<std::uint32_t>(nx)), d))];
      if (neighbour > outside) outside = neighbour;  // false for NaN
    }
    g.drop[d] = here - outside;
  }
  if (tilted_) tilt_faces(g);
  for (int d = 0; d < 4; ++d)
    if ((f & kOnEdgeBit[d]) && spec_.edges[kEdgeOfDirection[d]] != EdgeKind::kOpen) g.drop[d] = 0.0;
  block_covered_faces(cell, g);
  return g;
}

double GranularGrid::downhill_slope_tan(int i, int j) const {
  const auto cell = static_cast<std::uint32_t>(index(i, j));
  if (quanta_[cell] <= 0) return 0.0;
  const FaceGeometry g = face_geometry(cell);
  const double inv_d = 1.0 / spec_.cell_size_m;
  double steepest = 0.0;
  for (int d = 0; d < 4; ++d) {
    if (g.drop[d] <= 0.0) continue;
    const double normal = g.drop[d] * inv_d, tangential = g.tangential[d] * inv_d;
    steepest = std::max(steepest, std::sqrt(normal * normal + tangential * tangential));
  }
  return steepest;
}

void GranularGrid::compute_flux(std::uint32_t cell, const FaceGeometry& g, CellFlux& flux) const {
  const double threshold = (flags_[cell] & kFlowing) ? law_.tan_stop : law_.tan_repose;
  const double inv_d = 1.0 / spec_.cell_size_m;
  double q[4];
  for (int d = 0; d < 4; ++d) q[d] = face_flux_quanta(g.drop[d], g.tangential[d], inv_d, threshold * threshold, law_);
  flux.cell = cell;
  flux.out = clamp_to_available(q, sendable_quanta(cell));
}

__attribute__((always_inline)) inline std::array<std::int32_t, 4> GranularGrid::clamp_to_available(
    const double q[4], std::int64_t available) {
  std::int64_t out[4];
  std::int64_t total = 0;
  for (int d = 0; d < 4; ++d) {
    out[d] = static_cast<std::int64_t>(q[d]);
    total += out[d];
  }
  if (total > available) {
    // Never below the base: scale every outflow of this cell by one factor,
    // then hand the quanta the rounding left over (fewer than 4) to the faces
    // in a fixed order, so the cell sends exactly what it holds. (Rounding
    // down alone could send nothing from a cell of 1-3 quanta with several
    // faces flowing while it would send from one face under the higher
    // static threshold: stopping must never depend on the threshold.)
    std::int64_t sent = 0;
    for (auto& o : out) {
      o = static_cast<std::int64_t>((static_cast<Int128>(o) * available) / total);
      sent += o;
    }
    for (int d = 0; d < 4 && sent < available; ++d) {
      if (q[d] < 1.0) continue;  // only faces that flow
      ++out[d];
      ++sent;
    }
  }
  return {static_cast<std::int32_t>(out[0]), static_cast<std::int32_t>(out[1]), static_cast<std::int32_t>(out[2]),
          static_cast<std::int32_t>(out[3])};
}

void GranularGrid::record_flow(bool on) {
  flow_x_.assign(on ? quanta_.size() : 0, 0);
  flow_y_.assign(on ? quanta_.size() : 0, 0);
}

void GranularGrid::sweep() {
  // A tilted grid's faces need the world slopes (tilt_faces): the sparse
  // path only (such grids are small).
  if (tilted_ && pending_all_) {
    pending_all_ = false;
    for (std::uint32_t c = 0; c < quanta_.size(); ++c) wake(static_cast<int>(c));
  }
  const bool dense = !tilted_ && slide_speed_.empty() && (mode_ == SweepMode::kDense ||
                                  (mode_ == SweepMode::kAuto && active_cell_count() * kDenseFraction > quanta_.size()));
  ++sweep_count_;
  if (dense) {
    sweep_dense();
    pending_all_ = mode_ != SweepMode::kSparse && changed_count_ * kDenseFraction > quanta_.size();
    if (pending_all_) return;  // the next sweep visits every cell anyway
    // Back to lists: after a dense sweep the cells that changed are exactly
    // those flagged as flowing.
    changed_.clear();
    for (std::uint32_t c = 0; c < quanta_.size(); ++c)
      if (flags_[c] & kFlowing) changed_.push_back(c);
  } else {
    sweep_sparse();
  }
  // The next active set: only cells whose 3 x 3 neighbourhood changed can
  // become unstable, so a terrain at rest is empty.
  for (std::uint32_t c : changed_) wake(static_cast<int>(c));
}

void GranularGrid::sweep_sparse() {
  current_.swap(pending_);
  pending_.clear();
  for (std::uint32_t c : current_) flags_[c] &= static_cast<std::uint8_t>(~(kQueued | kBlockQueued));
  if (shuffle_seed_ != 0) {
    std::uint64_t state = shuffle_seed_ ^ (sweep_count_ * 0x2545F4914F6CDD1Dull);
    for (std::size_t k = current_.size(); k > 1; --k)
      std::swap(current_[k - 1], current_[split_mix(state) % k]);
  }

  // Phase 1: every flux from the state at the start of the sweep.
  flux_.resize(current_.size());
  sparse_fluxes();

  // Phase 2: apply. Integer sums commute, so the visiting order cannot change
  // the result, and what leaves one cell arrives in another or off-site.
  const int offset[4] = {1, -1, spec_.nx, -spec_.nx};
  const auto mark_changed = [this](std::uint32_t c) {
    if (!(flags_[c] & kChanged)) {
      flags_[c] |= kChanged;
      changed_.push_back(c);
    }
  };
  changed_.clear();
  for (const CellFlux& flux : flux_) {
    const std::int64_t total = std::int64_t{flux.out[0]} + flux.out[1] + flux.out[2] + flux.out[3];
    ++last_step_.cells_checked;
    if (total == 0) continue;
    ++last_step_.cells_toppled;
    last_step_.moved_quanta += total;
    const std::uint32_t c = flux.cell;
    quanta_[c] -= total;
    mark_changed(c);
    if (!flow_x_.empty()) {
      flow_x_[c] += std::int64_t{flux.out[0]} - flux.out[1];
      flow_y_[c] += std::int64_t{flux.out[2]} - flux.out[3];
    }
    const std::uint8_t f = flags_[c];
    for (int d = 0; d < 4; ++d) {
      if (flux.out[d] == 0) continue;
      if (!(f & kOnEdgeBit[d])) {
        quanta_[c + offset[d]] += flux.out[d];
        loosen(c + offset[d], flux.out[d]);  // what slid lies loose on its new cell
        mark_changed(c + offset[d]);
      } else {
        send_over_edge(c, d, flux.out[d]);
      }
    }
  }
  // Every flowing cell was changed in the previous sweep and so is in this
  // one's active set: clearing I here covers all cells that stopped.
  for (std::uint32_t c : current_) flags_[c] &= static_cast<std::uint8_t>(~kFlowing);
  // Flowing flags (4.5) and surfaces of the cells that changed.
  for (std::uint32_t c : changed_) {
    flags_[c] = static_cast<std::uint8_t>((flags_[c] & ~kChanged) | kFlowing);
    refresh_surface(static_cast<int>(c));
  }
}

void GranularGrid::sweep_dense() {
  // The same sweep over every cell, row by row, with no lists. A cell outside
  // the active set is stable with an unchanged neighbourhood, so its flux is
  // exactly zero and the result is that of the sparse sweep.
  for (std::uint32_t c : pending_) flags_[c] &= static_cast<std::uint8_t>(~(kQueued | kBlockQueued));
  pending_.clear();
  pending_all_ = false;
  const int nx = spec_.nx, ny = spec_.ny;
  // The two phases are fused row by row: the fluxes of row j + 1 are computed
  // (from rows j..j+2, still unchanged) before row j gathers what rows j - 1,
  // j and j + 1 send it, so only three rows of fluxes are kept.
  dense_rows_.resize(static_cast<std::size_t>(3) * nx);
  const auto row_fluxes = [this, nx](int j) { return dense_rows_.data() + static_cast<std::size_t>(j % 3) * nx; };
  changed_count_ = 0;
  dense_row_fluxes(0, row_fluxes(0));
  for (int j = 0; j < ny; ++j) {
    if (j + 1 < ny) dense_row_fluxes(j + 1, row_fluxes(j + 1));
    gather_row(j, j > 0 ? row_fluxes(j - 1) : nullptr, row_fluxes(j), j + 1 < ny ? row_fluxes(j + 1) : nullptr);
  }
  last_step_.cells_checked += static_cast<std::int64_t>(nx) * ny;
}

void GranularGrid::gather_row(int j, const std::array<std::int32_t, 4>* below,
                              const std::array<std::int32_t, 4>* here, const std::array<std::int32_t, 4>* above) {
  // What a cell keeps plus what its four neighbours send it. The row's own
  // fluxes and those of the rows beside it are all computed, so its flags
  // and surfaces are updated in place.
  const int nx = spec_.nx;
  const auto row = static_cast<std::uint32_t>(j * nx);
  std::int64_t* __restrict quanta = quanta_.data() + row;
  double* __restrict surface = surface_m_.data() + row;
  const float* __restrict base = base_m_.data() + row;
  std::uint8_t* __restrict flags = flags_.data() + row;
  std::int64_t toppled = 0, moved = 0;
  std::size_t changed_count = 0;
  std::int64_t* flow_x = flow_x_.empty() ? nullptr : flow_x_.data() + row;
  std::int64_t* flow_y = flow_y_.empty() ? nullptr : flow_y_.data() + row;
  const auto gather = [&](int i, std::int64_t received) {
    const std::int64_t sent = std::int64_t{here[i][0]} + here[i][1] + here[i][2] + here[i][3];
    if (flow_x) {
      flow_x[i] += std::int64_t{here[i][0]} - here[i][1];
      flow_y[i] += std::int64_t{here[i][2]} - here[i][3];
    }
    toppled += sent != 0;
    moved += sent;
    const bool changed = (sent != 0) | (received != 0);
    const std::int64_t now = quanta[i] + received - sent;
    quanta[i] = now;
    surface[i] = base[i] + now * kHeightQuantumM;
    flags[i] = static_cast<std::uint8_t>((flags[i] & ~kFlowing) | (changed ? kFlowing : 0));
    changed_count += changed;
  };
  // Cells on the grid's edges: neighbours may be missing, and what crosses an
  // open edge goes off-site.
  const auto gather_edge_cell = [&](int i) {
    const std::uint8_t f = flags[i];
    std::int64_t received = 0;
    if (!(f & kOnEdgeBit[1])) received += here[i - 1][0];
    if (!(f & kOnEdgeBit[0])) received += here[i + 1][1];
    if (!(f & kOnEdgeBit[3])) received += below[i][2];
    if (!(f & kOnEdgeBit[2])) received += above[i][3];
    for (int d = 0; d < 4; ++d)
      if ((f & kOnEdgeBit[d]) && here[i][d] != 0) send_over_edge(row + static_cast<std::uint32_t>(i), d, here[i][d]);
    gather(i, received);
  };
  if (j == 0 || j == spec_.ny - 1 || nx < 3) {
    for (int i = 0; i < nx; ++i) gather_edge_cell(i);
  } else {
    gather_edge_cell(0);
    for (int i = 1; i < nx - 1; ++i)
      gather(i, std::int64_t{here[i - 1][0]} + here[i + 1][1] + below[i][2] + above[i][3]);
    gather_edge_cell(nx - 1);
  }
  last_step_.cells_toppled += toppled;
  last_step_.moved_quanta += moved;
  changed_count_ += changed_count;
}

// Phase 1 of the dense sweep. Inner rows go through a loop over cells that
// the compiler vectorises (cloned for AVX2 where the processor has it); the
// arithmetic per face is that of compute_flux, so results are bit-identical
// (IEEE sqrt and division, no fused multiply-add: -ffp-contract=off).
__attribute__((target_clones("avx2", "default"))) void GranularGrid::dense_row_fluxes(
    int j, std::array<std::int32_t, 4>* out) {
  const int nx = spec_.nx;
  const auto row = static_cast<std::uint32_t>(j * nx);
  CellFlux flux;
  const auto edge_cell = [&](int i) {
    compute_flux(row + static_cast<std::uint32_t>(i), face_geometry(row + static_cast<std::uint32_t>(i)), flux);
    out[i] = flux.out;
  };
  if (j == 0 || j == spec_.ny - 1 || nx < 3) {
    for (int i = 0; i < nx; ++i) edge_cell(i);
    return;
  }
  const double* h = surface_m_.data();
  const std::uint8_t* flags = flags_.data();
  const double inv_d = 1.0 / spec_.cell_size_m;
  const double stop2 = law_.tan_stop * law_.tan_stop, repose2 = law_.tan_repose * law_.tan_repose;
  const FlowLaw law = law_;
  row_q_.resize(static_cast<std::size_t>(4) * nx);
  double* q = row_q_.data();
  for (int i = 1; i < nx - 1; ++i) {
    const int c = static_cast<int>(row) + i;
    const FaceGeometry g = face_geometry_from(h[c], h[c + 1], h[c - 1], h[c + nx], h[c - nx], h[c + 1 + nx],
                                              h[c - 1 + nx], h[c + 1 - nx], h[c - 1 - nx]);
    const double threshold2 = (flags[c] & kFlowing) ? stop2 : repose2;
    q[4 * i + 0] = face_flux_quanta(g.drop[0], g.tangential[0], inv_d, threshold2, law);
    q[4 * i + 1] = face_flux_quanta(g.drop[1], g.tangential[1], inv_d, threshold2, law);
    q[4 * i + 2] = face_flux_quanta(g.drop[2], g.tangential[2], inv_d, threshold2, law);
    q[4 * i + 3] = face_flux_quanta(g.drop[3], g.tangential[3], inv_d, threshold2, law);
  }
  if (covered_count_ != 0) {
    // Bodies in the way (kept out of the loop above, which must stay
    // vectorised): no flux across a face of, or towards, a covered cell.
    const int offset[4] = {1, -1, nx, -nx};
    for (int i = 1; i < nx - 1; ++i) {
      const int c = static_cast<int>(row) + i;
      for (int d = 0; d < 4; ++d)
        if ((flags[c] | flags[c + offset[d]]) & kCovered) q[4 * i + d] = 0.0;
    }
  }
  const std::int64_t* __restrict available = quanta_.data() + row;
  if (held_count_ == 0) {
    for (int i = 1; i < nx - 1; ++i) out[i] = clamp_to_available(q + 4 * i, available[i]);
  } else {
    for (int i = 1; i < nx - 1; ++i) out[i] = clamp_to_available(q + 4 * i, sendable_quanta(row + i));
  }
  edge_cell(0);
  edge_cell(nx - 1);
}

// Phase 1 of the sparse sweep, in blocks of active cells: their face
// geometry is gathered into flat arrays and the face fluxes computed in one
// loop that vectorises, with the arithmetic of compute_flux.
__attribute__((target_clones("avx2", "default"))) void GranularGrid::sparse_fluxes() {
  if (!slide_speed_.empty()) {
    slippage_fluxes();
    return;
  }
  const double inv_d = 1.0 / spec_.cell_size_m;
  const double stop2 = law_.tan_stop * law_.tan_stop, repose2 = law_.tan_repose * law_.tan_repose;
  const FlowLaw law = law_;
  double drop[4 * kFluxBlock], tangential[4 * kFluxBlock], threshold2[4 * kFluxBlock], q[4 * kFluxBlock];
  for (std::size_t start = 0; start < current_.size(); start += kFluxBlock) {
    const std::size_t count = std::min(kFluxBlock, current_.size() - start);
    for (std::size_t k = 0; k < count; ++k) {
      const std::uint32_t c = current_[start + k];
      const FaceGeometry g = face_geometry(c);
      const double t2 = (flags_[c] & kFlowing) ? stop2 : repose2;
      for (int d = 0; d < 4; ++d) {
        drop[4 * k + d] = g.drop[d];
        tangential[4 * k + d] = g.tangential[d];
        threshold2[4 * k + d] = t2;
      }
    }
    for (std::size_t f = 0; f < 4 * count; ++f)
      q[f] = face_flux_quanta(drop[f], tangential[f], inv_d, threshold2[f], law);
    for (std::size_t k = 0; k < count; ++k) {
      const std::uint32_t c = current_[start + k];
      flux_[start + k].cell = c;
      flux_[start + k].out = clamp_to_available(q + 4 * k, sendable_quanta(c));
    }
  }
}

void GranularGrid::slippage_fluxes() {
  const double d = spec_.cell_size_m, inv_d = 1.0 / d, dt = slip_.sweep_dt_s;
  SlippageLaw remoulded = slip_;  // the loose layer: no cohesion
  remoulded.cohesion_length_m = 0.0;
  for (std::size_t k = 0; k < current_.size(); ++k) {
    const std::uint32_t c = current_[k];
    const FaceGeometry g = face_geometry(c);
    // The intact soil's slices first; where none fails, the loose layer on
    // top may still slide by friction alone, but no more than it holds.
    const std::int64_t loose = std::min(loose_[c], quanta_[c]);
    bool intact_fails = false;
    SliceFailure failure[4];
    double tan_beta[4] = {1.0, 1.0, 1.0, 1.0};
    for (int f = 0; f < 4; ++f) {
      if (!(g.drop[f] > 0.0)) continue;
      tan_beta[f] = std::hypot(g.drop[f], g.tangential[f]) * inv_d;
      failure[f] = slice_failure(slip_, tan_beta[f] * d, d);
      intact_fails |= failure[f].fails;
    }
    if (!intact_fails && loose > 0 && slip_.cohesion_length_m > 0.0)
      for (int f = 0; f < 4; ++f)
        if (g.drop[f] > 0.0) failure[f] = slice_failure(remoulded, tan_beta[f] * d, d);
    double accel = 0.0;
    for (int f = 0; f < 4; ++f) accel = std::max(accel, failure[f].accel_m_s2);
    // (5.1): the wedge of the steepest failing slice speeds up; a stable
    // cell's wedge is held by friction and stops.
    float& speed = slide_speed_[c];
    const double v = accel > 0.0 && quanta_[c] > 0 ? std::min(speed + accel * dt, slip_.max_speed_m_s) : 0.0;
    // (4.2): the wedge (area run * excess / 2) moving at v sends
    // area * v * dt / run per unit width through the face; over a face d
    // wide into a cell d^2 that is excess * v * dt / (2 d) of height, the
    // face's share of the gradient-direction flux (normal / |slope|).
    double q[4];
    for (int f = 0; f < 4; ++f) {
      const double moved_m = 0.5 * failure[f].excess_m * v * dt * inv_d * (g.drop[f] * inv_d / tan_beta[f]);
      q[f] = failure[f].fails ? std::min(moved_m * (1.0 / kHeightQuantumM), 2.0e9) + 0.5 : 0.0;
    }
    flux_[k].cell = c;
    flux_[k].out = clamp_to_available(q, held(static_cast<int>(c)) ? 0 : intact_fails ? quanta_[c] : loose);
    const std::int64_t sent = std::int64_t{flux_[k].out[0]} + flux_[k].out[1] + flux_[k].out[2] + flux_[k].out[3];
    speed = sent != 0 ? static_cast<float>(v) : 0.0f;  // nothing moved: nothing slides
    // What leaves goes from the top, loose first. Only this cell's own entry
    // is written, so the sweep stays independent of the visiting order.
    take_from_top(c, sent);
  }
}

void GranularGrid::step() {
  last_step_ = StepStats{};
  last_step_.substeps = law_.substeps;
  for (int s = 0; s < law_.substeps && !at_rest(); ++s) sweep();
  if (last_step_.moved_quanta != 0) ++revision_;
}

}  // namespace skidsim::terrain
