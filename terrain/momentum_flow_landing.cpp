// The fast flow's landings (terrain/momentum_flow.h): material from a body
// joining the flowing layer with its horizontal momentum, and the pressure
// a landing whose sheet would cross a cell puts on the layer, shaped over
// its footprint as a stagnation flow's; docs/fast_flows.md, "Landing".
#include "terrain/momentum_flow.h"
#include "terrain/momentum_flow_cells.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace skidsim::terrain {

using namespace momentum_cells;

void MomentumFlow::land(const GranularGrid& grid, int cell, std::int64_t quanta, double vx_m_s, double vy_m_s, double vz_m_s) {
  if (quanta <= 0) return;
  const std::int64_t before = std::min(flowing_[cell], grid.loose_quanta(cell) - rain_[cell]);
  const std::int64_t after = std::min(std::max<std::int64_t>(before, 0) + quanta, grid.loose_quanta(cell) - rain_[cell]);
  if (after <= 0) return;
  // A landing presses on the layer where its sheet would cross a cell
  // (landing_presses); a slower one loses its fall as rain does.
  if (landing_presses(vz_m_s)) {  // the cell is marked below, so the next step takes it
    if (impact_pressure_[cell] == 0.0 && landed_m_[cell] == 0.0) impacted_.push_back(cell);
    landed_m2_s_[cell] += static_cast<double>(quanta) * kHeightQuantumM * -vz_m_s;
    landed_m_[cell] += static_cast<double>(quanta) * kHeightQuantumM;
  }
  // Each face the cell feeds (or that stands still) takes the mass-weighted
  // mean of its velocity and the landing's component across it; a face
  // feeding the cell belongs to its neighbour's layer and is left alone.
  const double w = static_cast<double>(after - std::max<std::int64_t>(before, 0)) / static_cast<double>(after);
  const std::array<int, 4> faces = faces_of(cell);
  const double along[4] = {vx_m_s, vx_m_s, vy_m_s, vy_m_s};
  for (int k = 0; k < 4; ++k) {
    double& u = face_u(k, faces[k]);
    if (u == 0.0 || leaves(k, u)) u = (1.0 - w) * u + (leaves(k, along[k]) ? w * along[k] : 0.0);
  }
  flowing_[cell] = after;
  fell_[cell] = 1;
  mark(cell);
}

void MomentumFlow::shape_impacts() {
  // The landings since the last step join each cell's pressure, which
  // relaxes over the time its stream takes to fall two cells: a stream
  // lands in pulses (a parcel per cell and half a cell's height), and its
  // footprint, read one step at a time, would be a scatter of cells each
  // pressing on its neighbours. The pressure's time integral is the
  // landings' momentum (over rho). A pressure whose push over a step is
  // under 0.1 mm/s has ended.
  const double ended = 1e-4 * d_ / step_dt_s_;
  std::size_t kept = 0;
  for (int c : impacted_) {
    if (landed_m_[c] > 0.0) impact_sheet_m_s_[c] = impact_c_ * landed_m2_s_[c] / landed_m_[c];  // c V
    const double fall_m_s = impact_sheet_m_s_[c] / impact_c_;
    const double keep = std::exp(-step_dt_s_ * fall_m_s / (2.0 * d_));
    impact_pressure_[c] = keep * impact_pressure_[c] + (1.0 - keep) * landed_m2_s_[c] / step_dt_s_;
    landed_m2_s_[c] = landed_m_[c] = 0.0;
    if (!(impact_pressure_[c] >= ended)) {  // (and a NaN ends)
      impact_pressure_[c] = impact_sheet_m_s_[c] = 0.0;
      continue;
    }
    impacted_[kept++] = c;
    mark(c);
  }
  impacted_.resize(kept);
  // Depth in cells from the footprint's edge (1 on its rim), breadth first.
  // The grid's border bounds no footprint (a strip one cell wide is a
  // slice of a wider one).
  auto inside = [&](int i, int j) { return i >= 0 && i < nx_ && j >= 0 && j < ny_; };
  auto landed = [&](int i, int j) { return inside(i, j) && impact_pressure_[j * nx_ + i] > 0.0; };
  static constexpr int kDi[4] = {1, -1, 0, 0}, kDj[4] = {0, 0, 1, -1};
  std::vector<int>& queue = impact_scratch_;
  queue.clear();
  for (int c : impacted_) {
    const int i = c % nx_, j = c / nx_;
    for (int k = 0; k < 4; ++k)
      if (inside(i + kDi[k], j + kDj[k]) && !landed(i + kDi[k], j + kDj[k])) {
        impact_depth_[c] = 1;
        queue.push_back(c);
        break;
      }
  }
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const int c = queue[q], i = c % nx_, j = c / nx_;
    for (int k = 0; k < 4; ++k) {
      if (!landed(i + kDi[k], j + kDj[k])) continue;
      const int nb = (j + kDj[k]) * nx_ + i + kDi[k];
      if (impact_depth_[nb] == 0) impact_depth_[nb] = impact_depth_[c] + 1, queue.push_back(nb);
    }
  }
  // A footprint with no rim (it covers its whole grid) is pressed evenly.
  for (int c : impacted_)
    if (impact_depth_[c] == 0) impact_depth_[c] = 1;
  // Each footprint's half-width R (its deepest cell, in cells), a cell's
  // distance from its middle r = R + 1/2 - D at depth D, and the
  // pressure's share there: 1 - (r / R)^2.
  for (int c : impacted_) {
    if (impact_depth_[c] < 0) continue;  // shaped with its footprint
    queue.clear();
    queue.push_back(c);
    int deepest = impact_depth_[c];
    impact_depth_[c] = -impact_depth_[c];
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const int a = queue[q], i = a % nx_, j = a / nx_;
      for (int k = 0; k < 4; ++k) {
        if (!landed(i + kDi[k], j + kDj[k])) continue;
        const int nb = (j + kDj[k]) * nx_ + i + kDi[k];
        if (impact_depth_[nb] <= 0) continue;
        deepest = std::max(deepest, impact_depth_[nb]);
        impact_depth_[nb] = -impact_depth_[nb];
        queue.push_back(nb);
      }
    }
    // Scaled so that the footprint bears the landings' whole pressure (the
    // floor's reaction is the momentum flux); landed_m2_s_ holds it, and
    // impact_reach_ r / R.
    const double r = static_cast<double>(deepest);
    double all = 0.0, shaped = 0.0;
    for (int a : queue) {
      const double x = (r + 0.5 + impact_depth_[a]) / r;  // depth is negative here
      all += impact_pressure_[a];
      landed_m2_s_[a] = std::max(0.0, 1.0 - x * x);
      impact_reach_[a] = x;
      shaped += landed_m2_s_[a];
    }
    for (int a : queue) landed_m2_s_[a] *= all / shaped;
  }
}

}  // namespace skidsim::terrain
