// Sessions (`skidsim bench --filter Session`): the real-time factor of the
// pile-to-zone session played by its script, at 10, 5 and 2.5 cm cells,
// with and without the state published over LCM (50 Hz, UDP multicast on
// this host), its site's fast flows off; and the fast flows' cost
// (BM_SessionFastFlowCost): the same first 45 simulated seconds at 5 cm
// with the site's fast_flow off and on, whose two rows of one run give the
// ratio (the rows above cover as many seconds as their minimum time allows,
// so a slower row covers an earlier, different stretch of the session).
// Figures go in the README; nothing here asserts a time.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "session/session.h"
#include "io/control_input.h"
#include "io/lcm_bridge.h"
#include "io/loader_files.h"
#include "io/operator_script.h"

namespace {

using namespace skidsim;

std::string source(const std::string& relative) {
  return (std::filesystem::path(io::default_loader_path()).parent_path().parent_path().parent_path() / relative)
      .string();
}

// The state over LCM, as `skidsim run` publishes it (50 Hz).
struct PublishState : session::SessionOutput {
  io::LcmBridge* bridge = nullptr;
  void state(const skidsim_lcm::state_t& m, double) override {
    if (bridge) bridge->publish_state(m);
  }
};

// The pile-to-zone exercise at `cell_m`, its site's fast flows as asked.
io::Exercise pile_to_zone_at(double cell_m, bool fast_flow) {
  io::Exercise ex = io::load_exercise(source("scenarios/pile_to_zone.xml"));
  ex.soils.front().cell_m = cell_m;
  ex.soils.front().fast_flow = fast_flow;
  return ex;
}

// The pile-to-zone session played by its script; start() begins it afresh.
struct ScriptedPileToZone {
  ScriptedPileToZone(double cell_m, bool fast_flow)
      : soils(io::load_soil_table(io::default_soil_table_path())),
        ex(pile_to_zone_at(cell_m, fast_flow)),
        loader(io::load_loader(ex.machine.loader)),
        script(io::load_operator_script(source("scenarios/pile_to_zone.operator.xml"))) {}
  void start() {
    session = std::make_unique<session::Session>(ex, loader, soils, session::SessionOptions{});
    op = std::make_unique<session::ScriptOperator>(script);
  }
  void stop() { op.reset(), session.reset(); }
  // One control tick; why the session ended at it, or "".
  std::string tick(session::SessionOutput& out) { return session->tick(false, decide, out); }
  const io::SoilTable soils;
  const io::Exercise ex;
  const vehicle::LoaderDescription loader;
  const io::OperatorScript script;
  std::unique_ptr<session::Session> session;
  std::unique_ptr<session::ScriptOperator> op;
  const session::DecideControls decide = [this](const skidsim_lcm::state_t& st, long, double t) { return op->decide(st, t); };
};

// One iteration: one simulated second of the session (100 control ticks of
// the session library: the script's player, the tasks' books, the timeline,
// 500 world steps), as `skidsim run` drives it, less the log. A session that
// ends (its tasks done) starts again, untimed. The site's fast flows off, as
// these rows were first measured (their cost: BM_SessionFastFlowCost).
void BM_SessionPileToZone(benchmark::State& state) {
  const double cell_m = static_cast<double>(state.range(0)) / 1000.0;
  const bool publish = state.range(1) != 0;
  ScriptedPileToZone run(cell_m, false);
  io::ControlInput input(0.2);
  std::unique_ptr<io::LcmBridge> bridge;
  if (publish) bridge = std::make_unique<io::LcmBridge>("udpm://239.255.76.67:7699?ttl=0", io::LcmChannels{}, &input);
  PublishState out;
  out.bridge = bridge.get();
  run.start();
  for (auto _ : state) {
    for (int tick = 0; tick < 100; ++tick)
      if (!run.tick(out).empty()) {
        state.PauseTiming();
        run.start();
        state.ResumeTiming();
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

// One iteration: a fresh pile-to-zone session at 5 cm played by its script
// for its first 45 simulated seconds (filling, carrying and the first dump),
// the site's fast_flow as the argument says; the same stretch both ways.
void BM_SessionFastFlowCost(benchmark::State& state) {
  const double tick_s = session::kStepsPerTick * engine::kStepSeconds;
  const int ticks_45_s = static_cast<int>(std::lround(45.0 / tick_s));
  const bool fast_flow = state.range(0) != 0;
  ScriptedPileToZone run(0.05, fast_flow);
  PublishState out;
  long ticks = 0;
  for (auto _ : state) {
    state.PauseTiming();
    run.start();
    state.ResumeTiming();
    for (int tick = 0; tick < ticks_45_s; ++tick) {
      ++ticks;
      if (!run.tick(out).empty()) break;
    }
    state.PauseTiming();
    run.stop();
    state.ResumeTiming();
  }
  state.counters["fast_flow"] = fast_flow ? 1.0 : 0.0;
  state.counters["sim_s_per_s"] = benchmark::Counter(tick_s * static_cast<double>(ticks), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SessionFastFlowCost)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

}  // namespace
