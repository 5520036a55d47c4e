#include "experiments/fed_heap.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "common/physical_constants.h"
#include "terrain/granular_grid.h"
#include "terrain/momentum_flow.h"

namespace skidsim::terrain {
namespace {

double x_of(const GranularGrid& g, int i) { return (i + 0.5) * g.cell_size_m(); }

// The slope of the least-squares line through the cells' heights between
// `from` and `to` (model scale), as a positive tangent downhill.
double fitted_tan(const GranularGrid& g, double from_m, double to_m) {
  double n = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (int i = 0; i < g.nx(); ++i) {
    const double x = x_of(g, i);
    if (x < from_m || x > to_m) continue;
    const double y = g.material_m(i, 0);
    n += 1.0, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return -(n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

FedHeapRun run_fed_heap(const FedHeapCase& c, const SoilFlowParameters& soil) {
  if (!(c.lambda > 0.0 && c.q_m2_s > 0.0 && c.cell_m > 0.0 && c.window_from_s >= 0.0 && c.window_from_s < c.duration_s))
    throw std::invalid_argument("fed heap: lambda, q_m2_s and cell_m must be > 0, the window's start within the run");
  const double length = c.length_m * c.lambda, time_scale = std::sqrt(c.lambda);
  GridSpec spec;
  spec.cell_size_m = c.cell_m;
  spec.nx = static_cast<int>(std::lround(length / c.cell_m));
  spec.ny = 1;
  spec.edges[kEdgeXMax] = EdgeKind::kOpen;  // the ledge; the wall and the row's sides closed
  if (spec.nx < 8) throw std::invalid_argument("fed heap: fewer than 8 cells along the heap");
  GranularGrid g(spec, soil, c.step_dt_s, 100000);
  for (int i = 0; i < spec.nx; ++i) g.set_material_m(i, 0, c.initial_tan * (length - x_of(g, i)));
  std::unique_ptr<MomentumFlow> flow;
  if (c.momentum) {
    MomentumFlowParameters p;
    p.grain_diameter_m = soil.grain_diameter_m * c.lambda;
    flow = std::make_unique<MomentumFlow>(g, p, c.step_dt_s);
  }

  // The feed: the cells whose centres lie in the band (at least the first;
  // a centre on the band's end counts, whatever the rounding).
  std::vector<int> fed;
  const double tolerance_m = 1e-9 * c.cell_m;
  for (int i = 0; i < spec.nx; ++i)
    if (x_of(g, i) >= c.feed_from_m * c.lambda - tolerance_m && x_of(g, i) <= c.feed_to_m * c.lambda + tolerance_m)
      fed.push_back(i);
  if (fed.empty()) fed.push_back(0);
  const double per_step_m3 = c.q_m2_s * std::pow(c.lambda, 1.5) * c.step_dt_s * c.cell_m / static_cast<double>(fed.size());

  const double land_v0_2 = c.feed_speed_m_s * c.feed_speed_m_s * c.lambda;
  const long steps = std::lround(c.duration_s * time_scale / c.step_dt_s);
  const long window_from = std::lround(c.window_from_s * time_scale / c.step_dt_s);
  const double fit_from = c.fit_from_m * c.lambda, fit_to = length - c.fit_to_edge_m * c.lambda;
  std::vector<double> tans;
  FedHeapRun run;
  run.books_exact = true;
  std::int64_t off_at_window = 0, fed_at_window = 0, fed_quanta = 0;
  for (long s = 1; s <= steps; ++s) {
    for (int i : fed) {
      const double fall_m = std::max(0.0, c.feed_height_m * c.lambda - g.material_m(i, 0));
      const double v_m_s = std::sqrt(land_v0_2 + 2.0 * kGravity_m_s2 * fall_m);
      const auto quanta = static_cast<std::int64_t>(std::llround(g.add_material_m3(i, 0, per_step_m3) / g.quantum_volume_m3()));
      if (flow && quanta > 0) flow->land(g, g.index(i, 0), quanta, 0.0, 0.0, -v_m_s);
      fed_quanta += quanta;
    }
    if (flow) flow->step(g);
    g.step();
    if (s == window_from) off_at_window = g.ledger().off_site_total(), fed_at_window = fed_quanta;
    if (s > window_from) tans.push_back(fitted_tan(g, fit_from, fit_to));
    if (s % 500 == 0) run.books_exact = run.books_exact && g.ledger().balanced();
  }
  run.books_exact = run.books_exact && g.ledger().balanced();
  double sum = 0.0, first = 0.0, second = 0.0;
  const std::size_t half = tans.size() / 2;
  for (std::size_t k = 0; k < tans.size(); ++k) (k < half ? first : second) += tans[k], sum += tans[k];
  run.tan_slope = sum / static_cast<double>(tans.size());
  run.tan_drift = second / static_cast<double>(tans.size() - half) - first / static_cast<double>(half);
  run.outflow_over_feed = static_cast<double>(g.ledger().off_site_total() - off_at_window) /
                          static_cast<double>(fed_quanta - fed_at_window);
  return run;
}

}  // namespace skidsim::terrain
