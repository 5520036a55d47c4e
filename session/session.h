// A training session as a library: built from an exercise in memory, driven
// one 10 ms control tick at a time, and reported. `skidsim run` wires it to
// LCM, the log and the frame recorder (apps/run_job.cpp); the performance
// report and the benchmarks drive it directly, with no file in between.
//
// One tick, in order: this tick's state message; the controls the caller's
// decision gives for it (a script's player, a replay, an operator over LCM);
// the tick's books (the applied controls, the tasks and their events, people
// and trucks released, the terrain's changed tiles, the report's timeline,
// the state out); then the world's 2 ms steps up to the next tick.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/world.h"
#include "io/exercise.h"
#include "io/soil_table.h"
#include "session/control_message.h"
#include "session/operator_player.h"
#include "session/session_tasks.h"
#include "session/terrain_tiles.h"
#include "skidsim_lcm/control_t.hpp"
#include "skidsim_lcm/event_t.hpp"
#include "skidsim_lcm/state_t.hpp"
#include "skidsim_lcm/terrain_tile_t.hpp"
#include "vehicle/loader_description.h"
#include "visual/scene_stream.h"

namespace skidsim::session {

// A session's cadences, in 2 ms world steps.
inline constexpr int kStepsPerTick = 5;      // controls every 10 ms
inline constexpr int kStepsPerState = 10;    // the state message at 50 Hz
inline constexpr int kStepsPerScene = 20;    // the scene stream (when asked for) at 25 Hz
inline constexpr int kStepsPerSample = 100;  // the report's timeline at 5 Hz
inline constexpr int kStepsPerTiles = 250;   // terrain tiles (when asked for) at 2 Hz

// Where a session's messages go: the log and LCM (skidsim run), or nowhere.
struct SessionOutput {
  virtual ~SessionOutput() = default;
  virtual void applied(const skidsim_lcm::control_t&, double /*t_s*/) {}
  virtual void event(const skidsim_lcm::event_t&, double /*t_s*/) {}
  virtual void state(const skidsim_lcm::state_t&, double /*t_s*/) {}
  virtual void tile(const skidsim_lcm::terrain_tile_t&, double /*t_s*/) {}
  // The scene stream (SessionOptions::scene_stream), with the state.
  virtual void scene(const skidsim_lcm::scene_t&, double /*t_s*/) {}
};

// A tick's controls, or why the session ends at it: `end_now` before the
// tick's books (the operator gone, a replay run out, a signal), `end_after`
// once they are kept (a script finished and settled), unless the tasks
// ended it first.
struct TickDecision {
  vehicle::LoaderControls controls;
  std::string end_now, end_after;
  bool watchdog_tripped = false;  // an event says the levers went to neutral
};
using DecideControls = std::function<TickDecision(const skidsim_lcm::state_t& state, long step, double t_s)>;

struct SessionOptions {
  double limit_s = 0.0;      // 0: the exercise's time limit
  long stop_at_step = -1;    // a replay: the step its recording ended at (-1: none)
  bool terrain_tiles = false;
  // The scene stream (visual/scene_stream.h) with every second state
  // message: what a view needs to draw the session; the soil's flow record
  // is kept for it.
  bool scene_stream = false;
};

class Session {
 public:
  Session(const io::Exercise& exercise, const vehicle::LoaderDescription& loader, const io::SoilTable& soils,
          const SessionOptions& options);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // One control tick (see the top of this file); `levers_neutral` goes into
  // the state message (the watchdog's neutral, for an operator over LCM);
  // `between` runs after the books and before the world steps (a recorder's
  // snapshot). Returns why the session ended at this tick, or "" to go on.
  std::string tick(bool levers_neutral, const DecideControls& decide, SessionOutput& out,
                   const std::function<void()>& between = {});
  // The end, at the step the world stopped at: the last tiles, the tasks'
  // final state and the "end" event.
  void finish(const std::string& end_reason, SessionOutput& out);

  // The report's parts every session has (report.json less how it was run).
  nlohmann::json report(const std::string& end_reason) const;
  // FNV-1a over what defines the final state (terrain, loads, poses, agents).
  std::uint64_t final_state_hash() const;

  const io::Exercise& exercise() const { return exercise_; }
  engine::World& world() { return *world_; }
  const engine::World& world() const { return *world_; }
  const SessionTasks& tasks() const { return *tasks_; }
  double limit_s() const { return limit_s_; }

 private:
  void keep_books(const skidsim_lcm::state_t& state, const TickDecision& decision, long step, double t, SessionOutput& out);
  void send_events(long step, double t, SessionOutput& out);

  io::Exercise exercise_;
  std::unique_ptr<engine::World> world_;
  std::unique_ptr<SessionTasks> tasks_;
  std::unique_ptr<TerrainTiles> tiles_;
  SessionOptions options_;
  double limit_s_;
  std::int64_t seq_ = 0;
  vehicle::LoaderControls controls_;  // held between ticks
  std::vector<std::vector<double>> timeline_;
  visual::SceneFrame scene_frame_;
  visual::SceneStreamWriter scene_writer_;
};

// A script played in-process: each tick's controls from its player; once it
// has finished, one more second to settle, then "script_done".
class ScriptOperator {
 public:
  explicit ScriptOperator(io::OperatorScript script) : player_(std::move(script)) {}
  TickDecision decide(const skidsim_lcm::state_t& state, double t_s);
  const OperatorPlayer& player() const { return player_; }

 private:
  OperatorPlayer player_;
  bool done_at_set_ = false;
  double done_at_s_ = 0.0;
};

}  // namespace skidsim::session
