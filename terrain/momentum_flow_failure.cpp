// The fast flow's failure (terrain/momentum_flow.h): the stable core under
// the examined cells, what fails above it, raining, and the layers thinner
// than h_stop lying down (in the failure and as a sub-step settles: fed,
// the front's feed); docs/fast_flows.md.
#include "terrain/momentum_flow.h"
#include "common/physical_constants.h"
#include "terrain/momentum_flow_cells.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace skidsim::terrain {

using namespace momentum_cells;

void MomentumFlow::raster_order_candidates() {
  // The failure's passes run in raster order. The listed flags inside the
  // examined cells' bounding box give that order in one scan, eight cells a
  // word where none is listed (a sort costs n log n comparisons).
  if (candidates_.size() < 2) return;
  int lo = candidates_[0], hi = lo, i_lo = nx_, i_hi = 0;
  for (int c : candidates_) {
    lo = std::min(lo, c), hi = std::max(hi, c);
    const int i = c % nx_;
    i_lo = std::min(i_lo, i), i_hi = std::max(i_hi, i);
  }
  candidates_.clear();
  for (int row = lo / nx_ * nx_; row <= hi; row += nx_) {
    const int last = row + i_hi;
    int c = row + i_lo;
    while (c <= last) {
      std::uint64_t word = 0;
      if (c + 8 <= last + 1) {
        std::memcpy(&word, &listed_[static_cast<std::size_t>(c)], sizeof word);
        if (word == 0) {
          c += 8;
          continue;
        }
      }
      if (listed_[static_cast<std::size_t>(c)]) candidates_.push_back(c);
      ++c;
    }
  }
}

bool MomentumFlow::fed(const GranularGrid& grid, int cell) const {
  // Faces moving into the cell from a neighbour's flowing layer; with the
  // taper, on to the thickest such neighbour while each is thicker than the
  // last (so the walk ends). Every cell the walk passes has the same answer
  // (its own walk is the rest of this one): with the taper they keep it for
  // the rest of the pass (feed_pass_), so a pass walks each taper once.
  if (taper_feed_) fed_path_.clear();
  bool found = false;
  while (true) {
    if (taper_feed_ && fed_stamp_[cell] == feed_pass_) {
      found = fed_memo_[cell] != 0;
      break;
    }
    if (taper_feed_) fed_path_.push_back(cell);
    const std::array<int, 4> f = faces_of(cell);
    const int i = cell % nx_, j = cell / nx_;
    const double into[4] = {-ux_face_[f[0]], ux_face_[f[1]], -uy_face_[f[2]], uy_face_[f[3]]};
    int upstream = -1;
    std::int64_t thickest = flowing_[cell];
    for (int k = 0; k < 4 && !found; ++k) {
      if (!(into[k] > 0.0)) continue;
      const int nb = neighbour(grid, i, j, k);
      if (nb < 0) continue;
      found = flowing_[nb] * kHeightQuantumM >= min_layer_m_;
      if (flowing_[nb] > thickest) {
        thickest = flowing_[nb];
        upstream = nb;
      }
    }
    if (found || !taper_feed_ || upstream < 0) break;
    cell = upstream;
  }
  if (taper_feed_) {
    for (int c : fed_path_) {
      fed_stamp_[c] = feed_pass_;
      fed_memo_[c] = found ? 1 : 0;
    }
  }
  return found;
}

void MomentumFlow::new_feed_pass() {
  if (!taper_feed_) return;
  if (++feed_pass_ == 0) {  // wrapped: no stamp may match a pass still to come
    std::fill(fed_stamp_.begin(), fed_stamp_.end(), 0u);
    feed_pass_ = 1;
  }
}

double MomentumFlow::bed_m(const GranularGrid& grid, int cell) const {
  return grid.surface_at(cell) - static_cast<double>(flowing_[cell] + rain_[cell]) * kHeightQuantumM;
}

double MomentumFlow::found_bed_m(const GranularGrid& grid, int cell) const {
  return std::isnan(event_bed_m_[cell]) ? bed_m(grid, cell) : event_bed_m_[cell];
}

bool MomentumFlow::bed_past_start(const GranularGrid& grid, int cell) const {
  const int i = cell % nx_, j = cell / nx_;
  const double here = found_bed_m(grid, cell), drop = bed_start_tan_ * d_;
  for (int k = 0; k < 4; ++k) {
    const int nb = neighbour(grid, i, j, k);
    if (nb >= 0 && here - found_bed_m(grid, nb) > drop) return true;
  }
  return false;
}

double MomentumFlow::erosion_floor_m(const GranularGrid& grid, int cell) const {
  // Anywhere where the bed stands past its start angle (or the soil has
  // none); else down to the bed the event found (what the flow laid on it
  // goes) or as low as it has been cut (a NaN found bed, outside an event:
  // the bed itself).
  if (!(bed_start_tan_ > 0.0) || bed_past_start(grid, cell)) return -std::numeric_limits<double>::infinity();
  return std::min(bed_m(grid, cell), event_bed_m_[cell]);
}

double MomentumFlow::layer_depth_m(const GranularGrid& grid, int cell, double flowing_m) const {
  using Depth = MomentumFlowParameters::LayerDepth;
  if (layer_depth_ == Depth::kFlowing || (layer_depth_ == Depth::kMobile && !erosion_)) return flowing_m;
  // The loose grains under the layer (compacted soil bears it as the hard base does).
  const double loose_bed_m = std::max(0.0, static_cast<double>(grid.loose_quanta(cell) - rain_[cell]) * kHeightQuantumM - flowing_m);
  if (layer_depth_ == Depth::kWhole) return flowing_m + loose_bed_m;
  return flowing_m + std::clamp(bed_m(grid, cell) - erosion_floor_m(grid, cell), 0.0, loose_bed_m);
}

void MomentumFlow::fail(const GranularGrid& grid, double dt_s) {
  // Failure: the examined cells' stable core is the highest surface under
  // the terrain whose slope nowhere exceeds the start angle (the repose
  // angle: the infinite-slope limit of soil at rest, docs/fast_flows.md),
  // or the thick layer's flowing friction (theta_1) up to a cell where a
  // layer moves (erosion of the metastable bed, Daerr and Douady 1999: the
  // bed under the layer is deep, so it is stable only to the angle at which
  // a thick layer stops; the DEM's deposits lie at about theta_1; a bed
  // only a few grains deep is held to theta_1 too, an approximation,
  // docs/fast_flows.md); with a bed start angle, erosion takes what this
  // flow event laid down (with laid_down_holds, not what a slowing layer
  // lays down: it joins the found bed), and the bed the event found only
  // where that bed, as the failure alone leaves it, stands past the start
  // angle (a deep bed at rest below it holds under a passing layer: the
  // DEM's erodible bed; the failure alone, not the erosion's cuts, so that
  // a notch cut into a bed below its start angle does not carry the bed
  // above it away);
  // everything above the core fails at once and joins the flowing layer,
  // the core stays. A column so keeps its
  // top while a < tan(repose) (Lajeunesse et al. 2004 and Lube et al. 2004
  // measured 0.7-0.74) and a peak fails
  // towards every lower side. The core is a chamfer distance transform
  // (8 neighbours) over the examined cells, the others standing at their
  // surface: Rosenfeld and Pfaltz's two raster passes, forward over the
  // neighbours before a cell and back over those after it, repeated until
  // nothing changes (the walls and the erosion's varying rise can ask for
  // more than one pair).
  rise_.resize(candidates_.size());
  bed_floor_m_.resize(candidates_.size());
  for (std::size_t n = 0; n < candidates_.size(); ++n) {
    const int c = candidates_[n];
    core_[c] = grid.surface_at(c);
    const bool erodes = erosion_ && flowing_[c] > 0;
    rise_[n] = d_ * (erodes ? mu_ : mu_start_);  // mu_ <= mu_start_ (constructor)
    if (!(bed_start_tan_ > 0.0)) continue;
    const double bed = bed_m(grid, c);
    if (std::isnan(event_bed_m_[c])) {
      event_bed_m_[c] = bed;
      in_event_.push_back(c);
    }
    // How low erosion may cut (judged on the found bed as the last pass left
    // it: on a cell's first sub-step, before its failure).
    bed_floor_m_[n] = erodes ? erosion_floor_m(grid, c) : -std::numeric_limits<double>::infinity();
  }
  relax_core(grid);
  // The new layers go to layer_ first, the faces' new momentum to keep_:
  // whether a thin layer is fed reads its neighbours as they were before
  // the pass.
  layer_.resize(candidates_.size());
  keep_.assign(candidates_.size(), 1.0);
  new_feed_pass();
  for (std::size_t n = 0; n < candidates_.size(); ++n) {
    const int c = candidates_[n];
    const std::int64_t q = grid.loose_quanta(c);
    // Less than h_stop above the core does not fail (it could not flow).
    std::int64_t failing = std::llround((grid.surface_at(c) - core_[c]) / kHeightQuantumM);
    if (failing * kHeightQuantumM < min_layer_m_) failing = 0;
    rain_[c] = std::min(rain_[c], q);
    std::int64_t flowing = std::max<std::int64_t>(0, std::min(flowing_[c], q - rain_[c]));
    if (raining_) {
      // Raining (Larrieu, Staron and Hinch 2006): what newly fails falls
      // freely in its cell, from rest, and lands on the layer beneath at its
      // fall's speed g t with no horizontal momentum (the column above stays
      // in contact with what it lands on). A cell whose rain has landed takes
      // what fails there afterwards into its flowing layer at once: the fall
      // is the release from rest, once an event (until nothing there fails).
      const std::int64_t newly = std::min(q, failing) - flowing - rain_[c];
      if (failing == 0) fell_[c] = 0;
      if (newly > 0 && fell_[c] && rain_[c] == 0) {
        flowing += newly;
      } else if (newly > 0) {
        if (rain_[c] == 0) rain_speed_[c] = 0.0;
        rain_[c] += newly;
      }
      if (rain_[c] > 0) {
        rain_speed_[c] += kGravity_m_s2 * dt_s;
        const std::int64_t lands =
            std::clamp<std::int64_t>(std::llround(rain_speed_[c] * dt_s / kHeightQuantumM), 1, rain_[c]);
        rain_[c] -= lands;
        if (rain_[c] == 0) fell_[c] = 1;
        // The faces this cell feeds carry its layer's momentum, now spread
        // over more mass (after the pass, like the layers).
        keep_[n] = flowing > 0 ? static_cast<double>(flowing) / static_cast<double>(flowing + lands) : 0.0;
        flowing += lands;
      }
    } else {
      flowing = std::min(q, std::max(flowing, failing));
    }
    // A layer thinner than h_stop does not flow (Pouliquen 1999; the soil's
    // min_flow_layer_m, scaled with the grains in a dimensionless
    // comparison): it lies down, and the automaton's slow regime has it;
    // unless a layer of at least h_stop still flows into it (the thin edge
    // of an advancing front, pushed on by the layer behind: laid down each
    // sub-step, it built a ramp the flow had to climb), or it slides on a
    // floor of its own (lies_down).
    layer_[n] = lies_down(grid, c, flowing) ? 0 : flowing;
  }
  for (std::size_t n = 0; n < candidates_.size(); ++n) {
    const int c = candidates_[n];
    flowing_[c] = layer_[n];
    if (keep_[n] == 1.0) continue;
    const std::array<int, 4> faces = faces_of(c);
    for (int k = 0; k < 4; ++k)
      if (leaves(k, face_u(k, faces[k]))) face_u(k, faces[k]) *= keep_[n];
  }
}

void MomentumFlow::relax_core(const GranularGrid& grid) {
  // Without a bed start angle (most soils) the passes do no more than the
  // erosion's and the start angle's one transform.
  if (bed_start_tan_ > 0.0) relax_core_passes<true>(grid);
  else relax_core_passes<false>(grid);
}

template <bool kTrack>
void MomentumFlow::relax_core_passes(const GranularGrid& grid) {
  // The neighbours before a cell in raster order as (di, dj); those after it are their opposites.
  constexpr int kBefore[4][2] = {{-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
  auto relax = [&](std::size_t n, int sign) {
    const int c = candidates_[n], i = c % nx_, j = c / nx_;
    const double rise = rise_[n], rise_diag = rise * std::sqrt(2.0);
    [[maybe_unused]] const double start = d_ * mu_start_, start_diag = start * std::sqrt(2.0);
    // `core` under the cell's rise (the erosion's where a layer moves);
    // with a bed start angle, `kept` under the start angle's and `found`,
    // the bed the event found as the failure alone (no erosion) leaves it,
    // under the start angle's over the neighbours' found beds.
    double core = core_[c];
    [[maybe_unused]] double kept = core_[c], found = 0.0;
    if constexpr (kTrack) found = event_bed_m_[c];
    const auto level = [&](int nb) { return listed_[nb] ? core_[nb] : grid.surface_at(nb); };  // examined: its core
    if (i > 0 && j > 0 && i + 1 < nx_ && j + 1 < ny_) {
      // Inside the grid: the neighbours by offset.
      for (const auto& o : kBefore) {
        const int nb = c + sign * (o[0] + o[1] * nx_);
        if (grid.covered(nb)) continue;
        const bool diag = o[0] != 0 && o[1] != 0;
        core = std::min(core, level(nb) + (diag ? rise_diag : rise));
        if constexpr (kTrack) {
          kept = std::min(kept, level(nb) + (diag ? start_diag : start));
          found = std::min(found, found_bed_m(grid, nb) + (diag ? start_diag : start));
        }
      }
    } else {
      for (const auto& o : kBefore) {
        const int di = sign * o[0], dj = sign * o[1], ni = i + di, nj = j + dj;
        const Edge edge = ni < 0 ? kEdgeXMin : ni >= nx_ ? kEdgeXMax : nj < 0 ? kEdgeYMin : kEdgeYMax;
        const int nb = cell_or_edge(grid, ni, nj, edge);
        const bool diag = di != 0 && dj != 0;
        if (nb == -2) continue;  // closed
        // A drop-off: bare base at the cell's own level.
        const double to = nb >= 0 ? level(nb) : static_cast<double>(grid.base_at(c));
        core = std::min(core, to + (diag ? rise_diag : rise));
        if constexpr (kTrack) {
          kept = std::min(kept, to + (diag ? start_diag : start));
          found = std::min(found, (nb >= 0 ? found_bed_m(grid, nb) : to) + (diag ? start_diag : start));
        }
      }
    }
    // Erosion cuts no lower than the bed's floor; the start angle holds
    // everywhere (without a bed start angle there is no floor, and the
    // erosion's core is already the lower).
    if constexpr (kTrack) core = std::min(kept, std::max(core, bed_floor_m_[n]));
    core = std::max(core, static_cast<double>(grid.base_at(c)));
    bool changed = core < core_[c];
    if constexpr (kTrack) {
      found = std::max(found, static_cast<double>(grid.base_at(c)));
      changed = changed || found < event_bed_m_[c];
      event_bed_m_[c] = found;
    }
    core_[c] = core;
    return changed;
  };
  // A forward pass leaves every cell within its rise of the neighbours
  // before it, a backward pass of those after it; so once a pass after the
  // first changes nothing, both hold and the core is found.
  for (int pass = 0; pass < 128; ++pass) {
    bool changed = false;
    if (pass % 2 == 0)
      for (std::size_t n = 0; n < candidates_.size(); ++n) changed = relax(n, 1) || changed;
    else
      for (std::size_t n = candidates_.size(); n-- > 0;) changed = relax(n, -1) || changed;
    if (!changed && pass > 0) break;
  }
}

void MomentumFlow::settle(const GranularGrid& grid) {
  // The moving cells: a flowing layer of at least h_stop with a face that
  // moves. A layer that has stopped, or thinned below h_stop, lies down as
  // static soil, and the faces it fed stand still.
  moving_.clear();
  for (int c : candidates_) {
    rain_[c] = std::min(rain_[c], grid.loose_quanta(c));
    flowing_[c] = std::min(flowing_[c], grid.loose_quanta(c) - rain_[c]);
  }
  layer_.resize(candidates_.size());
  new_feed_pass();
  for (std::size_t n = 0; n < candidates_.size(); ++n)
    layer_[n] = lies_down(grid, candidates_[n], flowing_[candidates_[n]]) ? 0 : flowing_[candidates_[n]];
  for (std::size_t n = 0; n < candidates_.size(); ++n) flowing_[candidates_[n]] = layer_[n];
  // Cells that only received this sub-step are among the candidates (the
  // moving cells' neighbours), so every changed layer is seen above.
  auto donor_still = [&](int face, bool x, double u) {
    // The donor: the cell on the face's minus side for u > 0, else its plus side.
    const int n = x ? nx_ + 1 : nx_, i = face % n, j = face / n;
    const int di = x && u > 0.0 ? -1 : 0, dj = !x && u > 0.0 ? -1 : 0;
    if (i + di < 0 || i + di >= nx_ || j + dj < 0 || j + dj >= ny_) return false;
    const int donor = grid.index(i + di, j + dj);
    return !grid.covered(donor) && flowing_[donor] > 0;
  };
  for (int f : x_faces_)
    if (ux_face_[f] != 0.0 && !donor_still(f, true, ux_face_[f])) ux_face_[f] = 0.0;
  for (int f : y_faces_)
    if (uy_face_[f] != 0.0 && !donor_still(f, false, uy_face_[f])) uy_face_[f] = 0.0;
  for (int c : candidates_) {
    if (rain_[c] > 0) {
      moving_.push_back(c);
      continue;
    }
    if (flowing_[c] == 0) continue;
    const std::array<int, 4> f = faces_of(c);
    const bool moves = ux_face_[f[0]] != 0.0 || ux_face_[f[1]] != 0.0 || uy_face_[f[2]] != 0.0 || uy_face_[f[3]] != 0.0;
    if (moves) moving_.push_back(c);
    else flowing_[c] = 0;
  }
}

}  // namespace skidsim::terrain
