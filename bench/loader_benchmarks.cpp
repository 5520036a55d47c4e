// The loader's 2 ms step (issue: the loader), run by `skidsim bench`.
// Figures go in the README; nothing here asserts a time.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "engine/demo_controls.h"
#include "engine/soil_site.h"
#include "engine/world.h"
#include "io/loader_files.h"
#include "io/soil_table.h"

namespace {

using namespace skidsim;

const vehicle::LoaderDescription& shipped_loader() {
  static const vehicle::LoaderDescription d = io::load_loader(io::default_loader_path());
  return d;
}

// Machine step on firm ground: multibody, tyres (a contact test each),
// hydraulics and drive. One iteration is one 2 ms step.
void BM_MachineStepFirm(benchmark::State& state) {
  engine::FirmGround ground;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation().z() = shipped_loader().tyre.radius_m - 0.01;
  engine::World world(shipped_loader(), ground, pose, 0.3, 0.0);
  long step = 0;
  for (int i = 0; i < 500; ++i) world.step(engine::circle_work_cycle(step++));
  for (auto _ : state) world.step(engine::circle_work_cycle(step++));
  state.counters["sim_s_per_s"] = benchmark::Counter(engine::kStepSeconds, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_MachineStepFirm)->Unit(benchmark::kMicrosecond);

// The machine driving a wide circle with its bucket cycling into 0.5 m of
// dry sand, on a square site of `side_m` at `cells_per_m` whose corner is
// at `corner_m` (the machine starts at (0, -3)). sim_s_per_s is the
// real-time factor.
void machine_work_cycle(benchmark::State& state, double cells_per_m, double side_m, const Eigen::Vector2d& corner_m) {
  const io::SoilRecord sand = io::load_soil_table(io::default_soil_table_path()).at("dry_sand");
  auto grid = engine::flat_soil_grid(sand.flow, cells_per_m, corner_m, side_m, side_m, 0.5);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.0, -3.0, 0.5 + shipped_loader().tyre.radius_m);
  engine::World world(shipped_loader(), engine::FirmGround{}, pose, 0.3, 0.0);
  world.add_soil_site(std::move(grid), sand.terramechanics);
  long step = 0;
  for (int i = 0; i < 500; ++i) world.step(engine::circle_work_cycle(step++));
  for (auto _ : state) world.step(engine::circle_work_cycle(step++));
  state.counters["sim_s_per_s"] = benchmark::Counter(engine::kStepSeconds, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["active_cells"] = static_cast<double>(world.terrain()->active_cell_count());
  state.counters["cells"] = static_cast<double>(world.terrain()->nx()) * world.terrain()->ny();
}

// On a 20 m x 20 m site centred on the work, at range(0) cells per metre:
// the wheels, chassis and bucket all press the sand and the terrain sweeps
// the ruts and spoil.
void BM_MachineOnSand(benchmark::State& state) {
  machine_work_cycle(state, static_cast<double>(state.range(0)), 20.0, Eigen::Vector2d(-10.0, -10.0));
}
BENCHMARK(BM_MachineOnSand)->Arg(10)->Arg(20)->Unit(benchmark::kMicrosecond);

// Level of detail by need: the same work in one corner of a 20 m or a
// 100 m square site (10 cm cells: 40,000 or 1,000,000 of them). Cells at
// rest and away from the machine cost nothing, so the step should cost the
// same on both.
void BM_MachineInACornerOfASite(benchmark::State& state) {
  machine_work_cycle(state, 10.0, static_cast<double>(state.range(0)), Eigen::Vector2d(-5.0, -5.0));
}
BENCHMARK(BM_MachineInACornerOfASite)->Arg(20)->Arg(100)->Unit(benchmark::kMicrosecond);

}  // namespace
