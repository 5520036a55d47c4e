#include "session/session.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "session/session_world.h"

namespace skidsim::session {

using nlohmann::json;

namespace {

// The report's plots over time, in this order (columnar).
const char* const kSeries[] = {"t_s", "chassis_x_m", "chassis_y_m", "speed_m_s", "bucket_payload_kg",
                               "material_moved_kg", "task_progress", "score", "engine_speed_rpm",
                               "tipping_margin", "max_wheel_slip"};
constexpr std::size_t kSeriesCount = sizeof(kSeries) / sizeof(kSeries[0]);

// What fell from the bodies (a dump, a spill) and whether every parcel had
// room to fall: one forced to land at once lands straight below, unfallen
// (terrain/material_exchange.h).
json falling_material(const engine::World& w) {
  const terrain::MaterialExchange* ex = w.material();
  if (!ex) return json(nullptr);
  const terrain::ExchangeStats& s = ex->stats();
  return {{"parcels_spawned", s.parcels_spawned}, {"parcels_forced_to_land", s.parcels_forced},
          {"parcels_in_flight_peak", s.parcels_in_flight_peak}, {"parcel_room", ex->max_parcels()}};
}

}  // namespace

Session::Session(const io::Exercise& exercise, const vehicle::LoaderDescription& loader, const io::SoilTable& soils,
                 const SessionOptions& options)
    : exercise_(exercise),
      world_(build_session_world(exercise_, loader, soils)),
      options_(options),
      limit_s_(options.limit_s > 0.0 ? options.limit_s : exercise.time_limit_s),
      timeline_(kSeriesCount) {
  check_tasks(exercise_, *world_);
  tasks_ = std::make_unique<SessionTasks>(exercise_, *world_);
  // The optional terrain channel: every tile at the start, then those that
  // changed, every kStepsPerTiles and at the end (so the log rebuilds the
  // final surface).
  if (options.terrain_tiles && world_->terrain()) tiles_ = std::make_unique<TerrainTiles>(*world_->terrain());
  if (options.scene_stream && world_->terrain()) world_->terrain()->record_flow(true);  // the state is untouched
  controls_.parking_brake = true;
  // Reserved: no reallocation in the loop.
  for (auto& series : timeline_)
    series.reserve(static_cast<std::size_t>(limit_s_ / (kStepsPerSample * engine::kStepSeconds)) + 2);
}

Session::~Session() = default;

std::string Session::tick(bool levers_neutral, const DecideControls& decide, SessionOutput& out,
                          const std::function<void()>& between) {
  engine::World& w = *world_;
  if (!(w.time_s() < limit_s_)) return "time_limit";
  if (options_.stop_at_step >= 0 && w.steps() >= options_.stop_at_step) return "replay_done";
  const long step = w.steps();
  const double t = w.time_s();
  skidsim_lcm::state_t state = machine_state(w, levers_neutral);
  state.score = tasks_->score();
  state.active_task = tasks_->active_task();
  const TickDecision decision = decide(state, step, t);
  if (!decision.end_now.empty()) return decision.end_now;
  controls_ = decision.controls;
  keep_books(state, decision, step, t, out);
  if (between) between();
  if (tasks_->all_done()) return "tasks_done";
  if (!decision.end_after.empty()) return decision.end_after;
  // The world's 2 ms steps up to the next tick (or the limit, or where a
  // replayed recording ended).
  do {
    w.step(controls_);
  } while (w.steps() % kStepsPerTick != 0 && w.time_s() < limit_s_ &&
           !(options_.stop_at_step >= 0 && w.steps() >= options_.stop_at_step));
  return "";
}

// The scene stream's rate is the most frames a second a recording draws.
static_assert(io::kMaxRecordFps * kStepsPerScene * engine::kStepSeconds > 1.0 - 1e-12 &&
              io::kMaxRecordFps * kStepsPerScene * engine::kStepSeconds < 1.0 + 1e-12);

void Session::keep_books(const skidsim_lcm::state_t& state, const TickDecision& decision, long step, double t,
                         SessionOutput& out) {
  engine::World& w = *world_;
  out.applied(to_message(controls_, ++seq_, step), t);
  tasks_->update(w, kStepsPerTick * engine::kStepSeconds, controls_);
  // Spawn events: an agent held for a task comes on site once it is done.
  for (std::size_t k = 0; k < exercise_.agents.size(); ++k)
    if (!exercise_.agents[k].start_after.empty() && w.agent_specs()[k].held)
      for (const TaskProgress& p : tasks_->tasks())
        if (p.id == exercise_.agents[k].start_after && p.done) w.release_agent(static_cast<int>(k));
  if (decision.watchdog_tripped)
    tasks_->add_event(t, "watchdog", "no command from the operator: levers to neutral, parking brake on", 1);
  send_events(step, t, out);
  if (tiles_ && step % kStepsPerTiles == 0)
    tiles_->send_changed(*w.terrain(), step, t, [&](const skidsim_lcm::terrain_tile_t& m) { out.tile(m, t); });
  if (step % kStepsPerSample == 0) {
    double progress_now = 0.0, worst_slip = 0.0;
    for (const TaskProgress& p : tasks_->tasks())
      if (p.id == state.active_task || (state.active_task.empty() && &p == &tasks_->tasks().back())) progress_now = p.progress;
    for (double slip : state.wheel_slip) worst_slip = std::max(worst_slip, std::abs(slip));
    const double sample[kSeriesCount] = {t,
                                         state.chassis_position_m[0],
                                         state.chassis_position_m[1],
                                         std::hypot(state.chassis_velocity_m_s[0], state.chassis_velocity_m_s[1]),
                                         state.bucket_payload_kg,
                                         tasks_->metrics().material_moved_kg,
                                         progress_now,
                                         tasks_->score(),
                                         state.engine_speed_rpm,
                                         state.tipping_margin,
                                         worst_slip};
    for (std::size_t k = 0; k < kSeriesCount; ++k) timeline_[k].push_back(sample[k]);
  }
  if (step % kStepsPerState == 0) {
    out.state(state, t);
    if (options_.scene_stream && step % kStepsPerScene == 0) {
      visual::capture_frame(w, scene_frame_);
      out.scene(scene_writer_.encode(scene_frame_), t);
    }
  }
}

void Session::send_events(long step, double t, SessionOutput& out) {
  for (const SessionEvent& e : tasks_->take_events()) {
    skidsim_lcm::event_t m{};
    m.step = step;
    m.sim_time_s = e.time_s;
    m.kind = e.kind;
    m.severity = static_cast<std::int8_t>(e.severity);
    m.text = e.text;
    out.event(m, t);
  }
}

void Session::finish(const std::string& end_reason, SessionOutput& out) {
  engine::World& w = *world_;
  if (tiles_)
    tiles_->send_changed(*w.terrain(), w.steps(), w.time_s(),
                         [&](const skidsim_lcm::terrain_tile_t& m) { out.tile(m, w.time_s()); });
  // The end, at the step the world stopped at: a replay stops there too.
  tasks_->finish(w);
  tasks_->add_event(w.time_s(), "end", "session ended: " + end_reason, 0);
  send_events(w.steps(), w.time_s(), out);
}

std::uint64_t Session::final_state_hash() const {
  const engine::World& w = *world_;
  std::uint64_t h = 1469598103934665603ull;
  const auto add = [&h](const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < n; ++k) h = (h ^ p[k]) * 1099511628211ull;
  };
  const auto add_grid = [&](const terrain::GranularGrid& g) {
    for (int c = 0; c < g.nx() * g.ny(); ++c) {
      const std::int64_t q = g.loose_quanta(c);
      add(&q, sizeof q);
    }
  };
  if (w.terrain()) add_grid(*w.terrain());
  if (w.bucket_material()) add_grid(w.bucket_material()->grid());
  for (int k = 0; k < w.tray_count(); ++k) add_grid(w.tray(k).grid());
  for (std::size_t k = 0; k < w.loader().description().links.size(); ++k) {
    const Eigen::Matrix4d pose = w.loader().link_pose(static_cast<int>(k)).matrix();
    add(pose.data(), sizeof(double) * 16);
  }
  const Eigen::Vector3d v = w.loader().chassis_velocity();
  add(v.data(), sizeof(double) * 3);
  // Where each agent is (none: nothing added, so exercises without agents
  // keep their hashes).
  for (const engine::AgentState& a : w.agents()) {
    add(a.body.position_m.data(), sizeof(double) * 2);
    add(a.body.velocity_m_s.data(), sizeof(double) * 2);
    add(&a.heading_rad, sizeof a.heading_rad);
  }
  return h;
}

json Session::report(const std::string& end_reason) const {
  const engine::World& w = *world_;
  const SessionTasks& tasks = *tasks_;
  json task_list = json::array();
  for (const TaskProgress& p : tasks.tasks())
    task_list.push_back({{"id", p.id}, {"type", p.type}, {"done", p.done}, {"done_at_s", p.done_at_s},
                         {"progress", p.progress}, {"detail", p.detail}});
  json metrics = json::object(), not_measured = json::array();
  for (const std::string& name : io::known_metrics()) {
    if (Metrics::measured(name)) {
      metrics[name] = tasks.metrics().value(name);
    } else {
      not_measured.push_back(name);
    }
  }
  // The score, term by term: weight x value of each scoring metric.
  json breakdown = json::array();
  for (const io::Metric& m : exercise_.scoring.metrics) {
    const double value = tasks.metrics().value(m.name);
    breakdown.push_back({{"metric", m.name}, {"weight", m.weight}, {"value", value}, {"points", m.weight * value}});
  }
  // People and trucks: where each ended, and what it was doing.
  json agents = json::array();
  static const char* const kPhases[] = {"not_yet", "moving", "pausing", "docked", "leaving", "gone"};
  for (std::size_t k = 0; k < w.agents().size(); ++k) {
    const engine::AgentState& a = w.agents()[k];
    agents.push_back({{"id", w.agent_specs()[k].id},
                      {"kind", w.agent_specs()[k].kind == engine::AgentKind::kTruck ? "truck" : "person"},
                      {"phase", kPhases[static_cast<int>(a.phase)]},
                      {"docked_at_s", a.docked_at_s},
                      {"position_m", {a.body.position_m.x(), a.body.position_m.y()}}});
  }
  json events = json::array();
  for (const SessionEvent& e : tasks.all_events())
    events.push_back({{"time_s", e.time_s}, {"kind", e.kind}, {"severity", e.severity}, {"text", e.text}});
  json timeline = json::object();
  for (std::size_t k = 0; k < kSeriesCount; ++k) timeline[kSeries[k]] = timeline_[k];
  char hash[32];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(final_state_hash()));
  return {
      {"exercise",
       {{"name", exercise_.name},
        {"file", exercise_.path},
        {"absolute_path", std::filesystem::absolute(exercise_.path).lexically_normal().string()}}},
      {"result",
       {{"passed", tasks.passed()},
        {"score", tasks.score()},
        {"pass_score", exercise_.scoring.pass_score},
        {"all_tasks_done", tasks.all_done()},
        {"tasks", task_list},
        {"score_breakdown", breakdown},
        {"script_phases_timed_out", json::array()}}},
      {"metrics", metrics},
      {"metrics_not_measured_yet", not_measured},
      {"passes", tasks.metrics().passes},
      {"agents", agents},
      {"peak_bucket_acceleration_m_s2", tasks.metrics().peak_bucket_acceleration_m_s2},
      {"events", events},
      {"timeline", timeline},
      {"final_state_hash", hash},
      {"end_reason", end_reason},
      {"machine_finite", w.events().finite},
      {"falling_material", falling_material(w)},
  };
}

TickDecision ScriptOperator::decide(const skidsim_lcm::state_t& state, double t_s) {
  TickDecision d;
  d.controls = player_.step(state);
  if (player_.done()) {
    if (!done_at_set_) {
      done_at_set_ = true;
      done_at_s_ = t_s;
    }
    if (t_s - done_at_s_ > 1.0) d.end_after = "script_done";  // the script has finished: one more second to settle
  }
  return d;
}

}  // namespace skidsim::session
