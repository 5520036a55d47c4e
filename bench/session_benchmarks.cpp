// Sessions (`skidsim bench --filter Session`): the real-time factor of the
// pile-to-zone session played by its script, at 10, 5 and 2.5 cm cells,
// with and without the state published over LCM (50 Hz, UDP multicast on
// this host). Figures go in the README; nothing here asserts a time.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>

#include "session/operator_player.h"
#include "session/session_tasks.h"
#include "session/session_world.h"
#include "io/control_input.h"
#include "io/lcm_bridge.h"
#include "io/loader_files.h"

namespace {

using namespace skidsim;

std::string source(const std::string& relative) {
  return (std::filesystem::path(io::default_loader_path()).parent_path().parent_path().parent_path() / relative)
      .string();
}

// One iteration: one simulated second of the session (500 steps, 100
// control ticks: the script's player, the tasks, the state at 50 Hz).
void BM_SessionPileToZone(benchmark::State& state) {
  const double cell_m = static_cast<double>(state.range(0)) / 1000.0;
  const bool publish = state.range(1) != 0;
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  io::Exercise ex = io::load_exercise(source("scenarios/pile_to_zone.xml"));
  ex.soils.front().cell_m = cell_m;
  const vehicle::LoaderDescription loader = io::load_loader(ex.machine.loader);
  auto world = apps::build_session_world(ex, loader, soils);
  apps::OperatorPlayer player(io::load_operator_script(source("scenarios/pile_to_zone.operator.xml")));
  apps::SessionTasks tasks(ex, *world);
  io::ControlInput input(0.2);
  std::unique_ptr<io::LcmBridge> bridge;
  if (publish) bridge = std::make_unique<io::LcmBridge>("udpm://239.255.76.67:7699?ttl=0", io::LcmChannels{}, &input);
  vehicle::LoaderControls controls;
  for (auto _ : state) {
    for (int s = 0; s < 500; ++s) {
      if (world->steps() % 5 == 0) {
        const skidsim_lcm::state_t st = apps::machine_state(*world, false);
        controls = player.step(st);
        tasks.update(*world, 0.01);
        if (bridge && world->steps() % 10 == 0) bridge->publish_state(st);
      }
      world->step(controls);
    }
  }
  state.counters["cell_mm"] = 1000.0 * cell_m;
  state.counters["sim_s_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SessionPileToZone)
    ->Args({100, 0})
    ->Args({50, 0})
    ->Args({50, 1})
    ->Args({25, 0})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

}  // namespace
