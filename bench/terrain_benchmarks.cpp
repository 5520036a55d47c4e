// Terrain automaton benchmarks (thesis table 7.1 and fig. 7.2), run by
// `skidsim bench`. Figures go in the README; nothing here asserts a time.
#include "common/physical_constants.h"
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "terrain/granular_grid.h"

namespace {

using skidsim::terrain::EdgeKind;
using skidsim::terrain::GranularGrid;
using skidsim::terrain::GridSpec;
using skidsim::terrain::SoilFlowParameters;

constexpr double kDt = 0.002;
constexpr double kCell = 0.05;

std::unique_ptr<GranularGrid> make_grid(int n, EdgeKind x_min_edge) {
  GridSpec spec;
  spec.nx = spec.ny = n;
  spec.cell_size_m = kCell;
  spec.edges = {EdgeKind::kClosed, EdgeKind::kClosed, EdgeKind::kClosed, EdgeKind::kClosed};
  spec.edges[skidsim::terrain::kEdgeXMin] = x_min_edge;
  return std::make_unique<GranularGrid>(spec, SoilFlowParameters{}, kDt);
}

// A plane at 60 degrees, draining over an open edge: every cell is unstable
// in every sweep (the thesis's all-active test case, table 7.1).
void fill_steep_plane(GranularGrid& g) {
  const double tan60 = std::tan(skidsim::deg_to_rad(60.0));
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i) g.set_material_m(i, j, 0.1 + (i + 1) * kCell * tan60);
}

void BM_AllActiveSweep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  auto grid = make_grid(n, EdgeKind::kOpen);
  fill_steep_plane(*grid);
  grid->step();  // reach the steady active-set size (and its scratch capacity)
  std::int64_t visits = 0;
  for (auto _ : state) {
    if (grid->active_cell_count() < static_cast<std::size_t>(n) * n) {
      state.PauseTiming();
      fill_steep_plane(*grid);
      grid->step();
      state.ResumeTiming();
    }
    grid->step();
    visits += grid->last_step().cells_checked;
  }
  state.counters["cells"] = static_cast<double>(n) * n;
  state.counters["per_cell"] = benchmark::Counter(static_cast<double>(visits),
                                                  benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["state_B_per_cell"] = static_cast<double>(GranularGrid::kStateBytesPerCell);
  state.counters["scratch_B_per_cell"] = static_cast<double>(grid->scratch_bytes()) / (static_cast<double>(n) * n);
}
// 5..30: the thesis's N (table 7.1; `skidsim bench report` puts them side by side).
BENCHMARK(BM_AllActiveSweep)->DenseRange(5, 30, 5)->Arg(64)->Arg(256)->Arg(1024)->Arg(2048)->Unit(benchmark::kMicrosecond);

// A large terrain with a layer at rest: a step must cost (almost) nothing.
void BM_TerrainAtRest(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  auto grid = make_grid(n, EdgeKind::kClosed);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) grid->set_material_m(i, j, 0.4);
  while (!grid->at_rest()) grid->step();
  for (auto _ : state) {
    grid->step();
    benchmark::DoNotOptimize(grid->active_cell_count());
  }
  state.counters["cells"] = static_cast<double>(n) * n;
  state.counters["state_MB"] = static_cast<double>(n) * n * GranularGrid::kStateBytesPerCell / 1e6;
}
BENCHMARK(BM_TerrainAtRest)->Arg(2048)->Unit(benchmark::kNanosecond);

// A hopper pouring 100 kg/s onto a 1024 x 1024 site (51 m at 5 cm): cost per
// step and active-set size as the cone grows (thesis fig. 7.2). The argument
// is the pouring time already elapsed, in seconds.
void BM_PourActiveSet(benchmark::State& state) {
  const int n = 1024;
  const double pour_s = static_cast<double>(state.range(0));
  auto grid = make_grid(n, EdgeKind::kClosed);
  const double volume_per_step = 100.0 * kDt / grid->soil().bulk_density_kg_m3;
  const auto pour_step = [&] {
    grid->add_material_m3(n / 2, n / 2, volume_per_step);
    grid->step();
  };
  for (int s = 0; s < static_cast<int>(pour_s / kDt); ++s) pour_step();
  double examined = 0, moving = 0;
  std::int64_t steps = 0;
  for (auto _ : state) {
    pour_step();
    examined += static_cast<double>(grid->last_step().cells_checked);
    moving += static_cast<double>(grid->last_step().cells_toppled);
    ++steps;
  }
  state.counters["examined"] = examined / static_cast<double>(steps);
  state.counters["moving"] = moving / static_cast<double>(steps);
  state.counters["cone_radius_cells"] = [&] {
    int r = 0;
    while (n / 2 + r < n && grid->material_m(n / 2 + r, n / 2) > 0.0) ++r;
    return static_cast<double>(r);
  }();
}
BENCHMARK(BM_PourActiveSet)->Arg(1)->Arg(4)->Arg(16)->Arg(64)->Unit(benchmark::kMicrosecond)->Iterations(500);

// The thesis's fig. 7.2 experiment: a cone just under the angle at which
// avalanches stop, fed at its apex; each addition sets off an avalanche that
// runs to rest. One iteration is one avalanche; the counters give the mean
// and the largest number of cells moving material per step against the
// cone's radius (in cells).
void BM_ConeAvalancheActiveSet(benchmark::State& state) {
  const int radius = static_cast<int>(state.range(0));
  const int n = 2 * radius + 21;
  auto grid = make_grid(n, EdgeKind::kClosed);
  const double tan_stop = std::tan(skidsim::deg_to_rad(grid->soil().stop_angle_deg));
  const int c = n / 2;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double r = std::hypot(i - c, j - c);
      if (r < radius) grid->set_material_m(i, j, 0.99 * tan_stop * kCell * (radius - r));
    }
  while (!grid->at_rest()) grid->step();
  const double drop_m3 = 0.02 * kCell * kCell;  // 2 cm of material on the apex cell
  double steps = 0, checked = 0, largest = 0;
  for (auto _ : state) {
    grid->add_material_m3(c, c, drop_m3);
    while (!grid->at_rest()) {
      grid->step();
      const auto moving = static_cast<double>(grid->last_step().cells_toppled);
      largest = std::max(largest, moving);
      checked += moving;
      ++steps;
    }
  }
  state.counters["mean_moving"] = checked / std::max(steps, 1.0);
  state.counters["max_moving"] = largest;
  state.counters["radius_cells"] = radius;
}
BENCHMARK(BM_ConeAvalancheActiveSet)->Arg(10)->Arg(20)->Arg(40)->Arg(80)->Unit(benchmark::kMicrosecond);

}  // namespace
