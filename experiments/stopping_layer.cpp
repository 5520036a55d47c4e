#include "experiments/stopping_layer.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "common/physical_constants.h"
#include "terrain/granular_grid.h"

namespace skidsim::terrain {

StoppingLayerRun run_stopping_layer(const StoppingLayerCase& c, const SoilFlowParameters& soil) {
  if (!(c.layer_m > 0.0 && c.speed_m_s > 0.0 && c.cell_m > 0.0 && c.length_m >= 16.0 * c.cell_m))
    throw std::invalid_argument("stopping layer: layer_m, speed_m_s and cell_m must be > 0, the strip 16 cells or more");
  if (c.on_floor && !(c.floor_friction_deg > 0.0 && c.floor_friction_deg < 89.0))
    throw std::invalid_argument("stopping layer: on the floor, floor_friction_deg must be in (0, 89)");
  GridSpec spec;
  spec.cell_size_m = c.cell_m;
  spec.nx = static_cast<int>(std::lround(c.length_m / c.cell_m));
  spec.ny = 1;
  // A deep bed at rest under the layer (the DEM's frozen grains stand for
  // it: the layer rubs on its own grains), or the bare floor.
  const double bed_m = c.on_floor ? 0.0 : 0.5;
  const int from = spec.nx / 8, to = spec.nx - spec.nx / 8;
  GranularGrid g(spec, soil, c.step_dt_s, 100000);
  for (int i = 0; i < spec.nx; ++i) g.set_material_m(i, 0, bed_m + (i >= from && i < to ? c.layer_m : 0.0));
  MomentumFlowParameters p;
  p.owns_cells = true;
  p.deposition = c.deposition;
  if (c.on_floor) p.floor_friction_deg = c.floor_friction_deg;
  MomentumFlow flow(g, p, c.step_dt_s);
  const std::int64_t layer = std::llround(c.layer_m / kHeightQuantumM);
  for (int i = from; i < to; ++i) flow.land(g, g.index(i, 0), layer, c.speed_m_s, 0.0);

  StoppingLayerRun run;
  // The deceleration the flow's own friction gives a layer h deep (the
  // soil's thin-layer law, Pouliquen 1999; the floor's on the floor).
  run.deceleration_m_s2 = kGravity_m_s2 * (c.on_floor ? flow.floor_friction_tan() : flow.bed_friction_tan(c.layer_m));
  // The middle third of the layer: its flowing layer's momentum over its
  // whole mass, and its flowing layer's mean speed.
  const int mid_from = spec.nx / 2 - spec.nx / 8, mid_to = spec.nx / 2 + spec.nx / 8;
  auto measure = [&](double& mean_m_s, double& flowing_m_s) {
    double momentum = 0.0, flowing = 0.0;
    for (int i = mid_from; i < mid_to; ++i) {
      const int cell = g.index(i, 0);
      momentum += flow.flowing_m(cell) * flow.velocity_x_m_s(cell);
      flowing += flow.flowing_m(cell);
    }
    mean_m_s = momentum / ((mid_to - mid_from) * c.layer_m);
    flowing_m_s = flowing > 0.0 ? momentum / flowing : 0.0;
  };
  double mean0 = 0.0, first = 0.0;
  measure(mean0, first);
  double mean = mean0, speed = first, t = 0.0;
  const int steps = static_cast<int>(std::ceil(c.max_time_s / c.step_dt_s));
  run.books_exact = true;
  for (int s = 0; s < steps; ++s) {
    flow.step(g);
    t += c.step_dt_s;
    const double before = mean;
    measure(mean, speed);
    run.travel_m += 0.5 * (before + mean) * c.step_dt_s;
    run.books_exact = run.books_exact && g.ledger().balanced();
    if (!(speed >= first / 20.0)) {
      run.stopped = true;
      run.t_stop_s = t;
      break;
    }
  }
  run.travel_ratio = run.travel_m * run.deceleration_m_s2 / (c.speed_m_s * c.speed_m_s);
  run.stop_time_ratio = run.t_stop_s * run.deceleration_m_s2 / c.speed_m_s;
  return run;
}

}  // namespace skidsim::terrain
