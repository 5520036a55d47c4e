// Terrain-body interaction benchmarks (thesis tables 7.4 and 7.5), run by
// `skidsim bench`. Figures go in the README; nothing here asserts a time.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "terrain/body_shapes.h"
#include "terrain/granular_grid.h"
#include "terrain/soil_contact.h"

namespace {

using namespace skidsim::terrain;

constexpr double kDt = 0.002;
constexpr double kSoilDepth = 0.4;

std::unique_ptr<GranularGrid> flat_site(double cells_per_m, double size_x_m, double size_y_m) {
  GridSpec spec;
  spec.cell_size_m = 1.0 / cells_per_m;
  spec.nx = static_cast<int>(std::lround(size_x_m * cells_per_m));
  spec.ny = static_cast<int>(std::lround(size_y_m * cells_per_m));
  auto g = std::make_unique<GranularGrid>(spec, SoilFlowParameters{}, kDt);
  for (int j = 0; j < spec.ny; ++j)
    for (int i = 0; i < spec.nx; ++i) g->set_material_m(i, j, kSoilDepth);
  return g;
}

// Table 7.4: a 1 m cube of 1 t resting on dry sand. One iteration is the
// contact map and the reaction of one step (SoilContactModel::interact);
// the cube has settled first, so this is the steady cost of a body at rest.
void BM_CubeContact(benchmark::State& state) {
  const double cells_per_m = static_cast<double>(state.range(0));
  auto grid = flat_site(cells_per_m, 2.0, 2.0);
  SoilContactModel model(*grid, SoilMechanics{});
  OrientedBox cube;
  cube.half_extents_m = Eigen::Vector3d::Constant(0.5);
  Eigen::Vector3d position(1.0137, 0.9871, kSoilDepth + 0.5);
  double vz = 0.0;
  const double mass = 1000.0;
  BodyMotion motion;
  for (int k = 0; k < 1500; ++k) {  // settle (implicit in the soil's stiffness)
    cube.centre_m = position;
    motion.reference_point_m = position;
    motion.linear_velocity_m_s = {0.0, 0.0, vz};
    const BodyReaction r = model.interact(0, cube, motion);
    const double stiffness = r.normal_stiffness_N_per_m, damping = r.normal_damping_N_s_per_m;
    vz = (mass * vz + kDt * (r.force_N.z() + damping * vz - mass * kGravity_m_s2)) /
         (mass + kDt * (kDt * stiffness + damping));
    position.z() += kDt * vz;
    grid->step();
  }
  cube.centre_m = position;
  motion.reference_point_m = position;
  motion.linear_velocity_m_s.setZero();
  int cells = 0;
  std::int64_t tests = 0;
  for (auto _ : state) {
    const BodyReaction r = model.interact(0, cube, motion);
    benchmark::DoNotOptimize(r.force_N);
    cells = r.contact_cells;
    tests = model.contact_map(0).segment_tests;
  }
  state.counters["contact_cells"] = cells;
  state.counters["segment_tests"] = static_cast<double>(tests);
  state.counters["sinkage_mm"] = 1000.0 * (kSoilDepth - (position.z() - 0.5));
}
// 5..30: the thesis's N (table 7.4; `skidsim bench report` puts them side by side), and 50.
BENCHMARK(BM_CubeContact)->DenseRange(5, 30, 5)->Arg(50)->Unit(benchmark::kMicrosecond);

// Table 7.5: the same cube pushed at 1 m/s through a 2 m x 6 m patch with
// its underside d0 below the surface. One iteration is one whole step:
// contact map, reaction, the soil pushed into the wedge and the avalanche
// sweep that spreads it. Every run is the same 4 m push (2000 steps), so
// the figures compare; the pile in front, and with it the cost and the
// resistance, grows along the push.
void BM_CubePush(benchmark::State& state) {
  const double cells_per_m = static_cast<double>(state.range(0));
  const double depth = 0.01 * static_cast<double>(state.range(1));
  std::unique_ptr<GranularGrid> grid;
  std::unique_ptr<SoilContactModel> model;
  OrientedBox cube;
  cube.half_extents_m = Eigen::Vector3d::Constant(0.5);
  BodyMotion motion;
  motion.linear_velocity_m_s = {1.0, 0.0, 0.0};
  const auto restart = [&] {
    grid = flat_site(cells_per_m, 6.0, 2.0);
    model = std::make_unique<SoilContactModel>(*grid, SoilMechanics{});
    cube.centre_m = {0.6137, 1.0013, kSoilDepth - depth + 0.5};
    // Start in a slot, as if pushed in.
    ContactMapper mapper;
    ContactMap map;
    mapper.build(*grid, cube, BodyMotion{}, &map);
    const double d = grid->cell_size_m();
    for (const CellContact& c : map.cells)
      grid->remove_material_m3(static_cast<int>(c.cell) % grid->nx(), static_cast<int>(c.cell) / grid->nx(),
                               c.covered_fraction * d * d * c.depth_m);
    motion.reference_point_m = cube.centre_m;
    model->embed(0, cube, motion);
    while (!grid->at_rest()) grid->step();
  };
  restart();
  double resistance = 0.0, last_resistance = 0.0;
  std::int64_t steps = 0;
  for (auto _ : state) {
    cube.centre_m.x() += kDt * motion.linear_velocity_m_s.x();
    motion.reference_point_m = cube.centre_m;
    const BodyReaction r = model->interact(0, cube, motion);
    grid->step();
    resistance += r.wedge[0].bound_N;
    last_resistance = r.wedge[0].bound_N;
    ++steps;
  }
  state.counters["mean_resistance_N"] = resistance / static_cast<double>(steps);
  state.counters["final_resistance_N"] = model->contact_map(0).cells.empty() ? 0.0 : last_resistance;
}
BENCHMARK(BM_CubePush)
    // The thesis's N and d0 (table 7.5; `skidsim bench report` puts them side by side), and 50 cells/m.
    ->ArgsProduct({{5, 10, 15, 20, 25, 30, 50}, {10, 15, 20, 25, 30}})
    ->ArgNames({"cells_per_m", "d0_cm"})
    ->Iterations(2000)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
