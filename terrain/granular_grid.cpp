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
  law_ = derive_flow_law(soil, spec.cell_size_m, step_dt_s, max_substeps);
  const std::size_t n = static_cast<std::size_t>(spec.nx) * spec.ny;
  quanta_.assign(n, 0);
  base_m_.assign(n, 0.0f);
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
  return total;
}

MaterialLedger GranularGrid::ledger() const {
  MaterialLedger out = ledger_;
  out.in_cells = total_quanta();
  return out;
}

std::size_t GranularGrid::scratch_bytes() const {
  return pending_.capacity() * sizeof(std::uint32_t) + current_.capacity() * sizeof(std::uint32_t) +
         changed_.capacity() * sizeof(std::uint32_t) + flux_.capacity() * sizeof(CellFlux);
}

void GranularGrid::wake(int cell) {
  const auto queue = [this](int c) {
    if (!(flags_[c] & kQueued)) {
      flags_[c] |= kQueued;
      pending_.push_back(static_cast<std::uint32_t>(c));
    }
  };
  const std::uint8_t f = flags_[cell];
  queue(cell);
  if (!(f & kOnEdgeBit[0])) queue(cell + 1);
  if (!(f & kOnEdgeBit[1])) queue(cell - 1);
  if (!(f & kOnEdgeBit[2])) queue(cell + spec_.nx);
  if (!(f & kOnEdgeBit[3])) queue(cell - spec_.nx);
}

void GranularGrid::set_base_m(int i, int j, double base_m) {
  if (!contains(i, j) || !std::isfinite(base_m)) throw std::invalid_argument("set_base_m: bad cell or value");
  base_m_[index(i, j)] = static_cast<float>(base_m);
  wake(index(i, j));
}

void GranularGrid::set_material_m(int i, int j, double material_m) {
  if (!contains(i, j) || !(material_m >= 0.0) || !std::isfinite(material_m))
    throw std::invalid_argument("set_material_m: bad cell or negative/non-finite height");
  const int c = index(i, j);
  const std::int64_t q = to_quanta(material_m);
  ledger_.initial += q - quanta_[c];
  quanta_[c] = q;
  wake(c);
}

double GranularGrid::add_material_m3(int i, int j, double volume_m3) {
  if (!contains(i, j) || !(volume_m3 >= 0.0) || !std::isfinite(volume_m3))
    throw std::invalid_argument("add_material_m3: bad cell or negative/non-finite volume");
  const int c = index(i, j);
  const std::int64_t q = std::llround(volume_m3 / quantum_volume_m3());
  if (q == 0) return 0.0;
  quanta_[c] += q;
  ledger_.added += q;
  // Poured material arrives moving: the cell flows (4.5) until it settles.
  flags_[c] |= kFlowing;
  wake(c);
  return q * quantum_volume_m3();
}

double GranularGrid::remove_material_m3(int i, int j, double volume_m3) {
  if (!contains(i, j) || !(volume_m3 >= 0.0) || !std::isfinite(volume_m3))
    throw std::invalid_argument("remove_material_m3: bad cell or negative/non-finite volume");
  const int c = index(i, j);
  const std::int64_t q = std::min<std::int64_t>(std::llround(volume_m3 / quantum_volume_m3()), quanta_[c]);
  if (q == 0) return 0.0;
  quanta_[c] -= q;
  ledger_.removed += q;
  wake(c);
  return q * quantum_volume_m3();
}

GranularGrid::FaceSlopes GranularGrid::face_slopes(std::uint32_t cell) const {
  const std::uint8_t f = flags_[cell];
  const int nx = spec_.nx;
  const auto height = [this](std::uint32_t c) { return base_m_[c] + quanta_[c] * kHeightQuantumM; };
  const double base = base_m_[cell];
  const double here = height(cell);
  const bool xp = !(f & kOnEdgeBit[0]), xm = !(f & kOnEdgeBit[1]);
  const bool yp = !(f & kOnEdgeBit[2]), ym = !(f & kOnEdgeBit[3]);
  // The 3 x 3 neighbourhood; outside the grid a cell repeats its neighbour
  // inside (zero gradient across the edge) for the tangential differences.
  const double e = xp ? height(cell + 1) : here, w = xm ? height(cell - 1) : here;
  const double n = yp ? height(cell + nx) : here, s = ym ? height(cell - nx) : here;
  const double ne = xp && yp ? height(cell + 1 + nx) : (xp ? e : n);
  const double nw = xm && yp ? height(cell - 1 + nx) : (xm ? w : n);
  const double se = xp && ym ? height(cell + 1 - nx) : (xp ? e : s);
  const double sw = xm && ym ? height(cell - 1 - nx) : (xm ? w : s);

  // The surface beyond each face: the neighbour; beyond an open edge the
  // imaginary neighbour sits at this cell's base (material falls off); a
  // closed edge is a wall (no drop).
  const double across[4] = {e, w, n, s};
  FaceSlopes out;
  for (int d = 0; d < 4; ++d) {
    double below = across[d];
    if (f & kOnEdgeBit[d]) below = spec_.edges[kEdgeOfDirection[d]] == EdgeKind::kOpen ? base : here;
    out.drop[d] = here - below;
  }
  // The gradient at each face centre: the normal part from the drop across
  // it, the tangential part from the four cells beside the face. Both are
  // centred on the face, so the slope magnitude is second-order accurate in
  // every direction: on a cone's diagonals a one-sided estimate would add
  // about 0.35 d/r to the slope and square the cone off.
  const double inv_d = 1.0 / spec_.cell_size_m;
  const double tangential[4] = {(n + ne - s - se) * 0.25 * inv_d, (n + nw - s - sw) * 0.25 * inv_d,
                                (e + ne - w - nw) * 0.25 * inv_d, (e + se - w - sw) * 0.25 * inv_d};
  for (int d = 0; d < 4; ++d) {
    const double normal = out.drop[d] * inv_d;
    out.tan_beta[d] = out.drop[d] > 0.0 ? std::sqrt(normal * normal + tangential[d] * tangential[d]) : 0.0;
  }
  return out;
}

double GranularGrid::downhill_slope_tan(int i, int j) const {
  const auto cell = static_cast<std::uint32_t>(index(i, j));
  if (quanta_[cell] <= 0) return 0.0;
  const FaceSlopes fs = face_slopes(cell);
  return std::max(std::max(fs.tan_beta[0], fs.tan_beta[1]), std::max(fs.tan_beta[2], fs.tan_beta[3]));
}

void GranularGrid::compute_flux(std::uint32_t cell, CellFlux& flux) const {
  flux.cell = cell;
  flux.out = {0, 0, 0, 0};
  const std::int64_t available = quanta_[cell];
  if (available <= 0) return;
  const FaceSlopes fs = face_slopes(cell);
  const double threshold = (flags_[cell] & kFlowing) ? law_.tan_stop : law_.tan_repose;

  // (4.16) as a finite-volume flux: through each downhill face whose slope
  // exceeds the threshold, the normal component of the flux vector
  // z+(beta) (tan beta - tan alpha_I) along the gradient. Each face flux is at
  // most z+ drop / d, which is what the stability bound rests on.
  const double inv_d = 1.0 / spec_.cell_size_m;
  std::int64_t out[4];
  std::int64_t total = 0;
  for (int d = 0; d < 4; ++d) {
    out[d] = 0;
    if (fs.tan_beta[d] <= threshold) continue;
    double q = law_.moved_height_m(fs.tan_beta[d]) * (fs.drop[d] * inv_d / fs.tan_beta[d]) / kHeightQuantumM;
    // One face carries at most 2 m per sweep; a higher cliff just takes more
    // sweeps (a smaller flux keeps the bound).
    q = q < 2.0e9 ? q : 2.0e9;
    out[d] = static_cast<std::int64_t>(q + 0.5);
    total += out[d];
  }
  if (total > available) {
    // Never below the base: scale every outflow of this cell by one factor.
    for (auto& o : out) o = static_cast<std::int64_t>((static_cast<Int128>(o) * available) / total);
  }
  for (int d = 0; d < 4; ++d) flux.out[d] = static_cast<std::int32_t>(out[d]);
}

void GranularGrid::sweep() {
  current_.swap(pending_);
  pending_.clear();
  for (std::uint32_t c : current_) flags_[c] &= static_cast<std::uint8_t>(~kQueued);
  if (shuffle_seed_ != 0) {
    std::uint64_t state = shuffle_seed_ ^ (sweep_count_ * 0x2545F4914F6CDD1Dull);
    for (std::size_t k = current_.size(); k > 1; --k)
      std::swap(current_[k - 1], current_[split_mix(state) % k]);
  }
  ++sweep_count_;

  // Phase 1: every flux from the state at the start of the sweep.
  flux_.resize(current_.size());
  for (std::size_t k = 0; k < current_.size(); ++k) compute_flux(current_[k], flux_[k]);

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
    const std::int64_t total =
        std::int64_t{flux.out[0]} + flux.out[1] + flux.out[2] + flux.out[3];
    ++last_step_.cells_checked;
    if (total == 0) continue;
    ++last_step_.cells_toppled;
    last_step_.moved_quanta += total;
    const std::uint32_t c = flux.cell;
    quanta_[c] -= total;
    mark_changed(c);
    const std::uint8_t f = flags_[c];
    for (int d = 0; d < 4; ++d) {
      if (flux.out[d] == 0) continue;
      if (!(f & kOnEdgeBit[d])) {
        quanta_[c + offset[d]] += flux.out[d];
        mark_changed(c + offset[d]);
      } else {
        ledger_.off_site[kEdgeOfDirection[d]] += flux.out[d];
      }
    }
  }

  // Phase 3: flowing flags (4.5) and the next active set. Only cells whose
  // neighbourhood changed can become unstable, so a terrain at rest is empty.
  for (std::uint32_t c : current_) flags_[c] &= static_cast<std::uint8_t>(~kFlowing);
  for (std::uint32_t c : changed_) {
    flags_[c] = static_cast<std::uint8_t>((flags_[c] & ~kChanged) | kFlowing);
    wake(static_cast<int>(c));
  }
}

void GranularGrid::step() {
  last_step_ = StepStats{};
  last_step_.substeps = law_.substeps;
  for (int s = 0; s < law_.substeps && !pending_.empty(); ++s) sweep();
}

}  // namespace skidsim::terrain
