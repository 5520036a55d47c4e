#include "apps/run_job.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <iterator>
#include <signal.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>

#include "visual/frame_recorder.h"
#include "session/operator_player.h"
#include "jobs/progress.h"
#include "report/report_html.h"
#include "jobs/run_directory.h"
#include "visual/scene_snapshot.h"
#include "session/session_replay.h"
#include "session/session_tasks.h"
#include "session/session_world.h"
#include "session/terrain_tiles.h"
#include "io/atomic_file.h"
#include "jobs/interrupt.h"
#include "io/control_input.h"
#include "io/lcm_bridge.h"
#include "io/loader_files.h"

namespace skidsim::apps {
namespace {

using nlohmann::json;

constexpr int kStepsPerTick = 5;        // controls every 10 ms
constexpr int kStepsPerState = 10;      // state published at 50 Hz
constexpr int kStepsPerSample = 100;    // the report's timeline at 5 Hz
constexpr int kStepsPerTiles = 250;     // terrain tiles (when asked for) at 2 Hz
constexpr int kMissedTicksToEnd = 25;   // lockstep: this many ticks in a row without a command ends the session

// FNV-1a over the bytes of what defines the final state: the terrain, the
// bucket's and beds' loads, every link's pose and the chassis's velocity,
// and where each agent is (none: nothing added, so exercises without
// agents keep their hashes).
std::uint64_t state_hash(const engine::World& w) {
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
  for (const engine::AgentState& a : w.agents()) {
    add(a.body.position_m.data(), sizeof(double) * 2);
    add(a.body.velocity_m_s.data(), sizeof(double) * 2);
    add(&a.heading_rad, sizeof a.heading_rad);
  }
  return h;
}

// Writes one message to the LCM log (readable by lcm-logplayer).
template <class Message>
void log_message(lcm::LogFile& log, const std::string& channel, const Message& m, double sim_time_s) {
  const int size = m.getEncodedSize();
  std::vector<unsigned char> buffer(static_cast<std::size_t>(size));
  m.encode(buffer.data(), 0, size);
  lcm::LogEvent e;
  e.eventnum = 0;
  e.timestamp = static_cast<std::int64_t>(sim_time_s * 1e6);
  e.channel = channel;
  e.datalen = size;
  e.data = buffer.data();
  log.writeEvent(&e);
}

}  // namespace

int run_session(const RunJob& job) {
  // From the start: a signal during setup ends the session at its first
  // tick, with its report, rather than killing it with a staging folder left.
  const jobs::InterruptScope interrupt_scope;
  const io::Exercise ex = io::load_exercise(job.exercise_path);
  const vehicle::LoaderDescription loader = io::load_loader(ex.machine.loader);
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  const SessionIdentity identity = session_identity(ex, loader, io::default_soil_table_path());  // the log's header
  const std::string script_path =
      !job.script_path.empty() ? job.script_path
                               : (ex.operator_source.kind == io::OperatorSource::Kind::kScript ? ex.operator_source.script : "");
  std::unique_ptr<OperatorPlayer> player;
  // A replay: the controls a recorded session applied, by control tick.
  std::vector<vehicle::LoaderControls> replay;
  const bool replaying = !job.replay_path.empty();
  long replay_end_step = -1;  // from the recording's "end" event
  if (replaying) {
    if (!script_path.empty() && !job.script_path.empty()) throw io::InputError("--replay and --script: give one");
    // The whole log checked, and its header against this exercise, before
    // anything runs (session/session_replay.h).
    Replay recorded = load_replay(job.replay_path, ex, identity, kStepsPerTick);
    replay = std::move(recorded.controls);
    replay_end_step = recorded.end_step;
  }
  if (!script_path.empty() && !replaying) player = std::make_unique<OperatorPlayer>(io::load_operator_script(script_path));
  const std::string mode = !job.mode.empty() ? job.mode : ((player || replaying) ? "fast" : "realtime");
  if (replaying && mode != "fast") throw io::InputError("--replay runs in mode fast");
  if (mode != "fast" && mode != "realtime" && mode != "lockstep")
    throw io::InputError("--mode '" + mode + "': expected fast, realtime or lockstep");
  if (mode == "lockstep" && (player || replaying))
    throw io::InputError("--mode lockstep waits for an operator over LCM; a script played in-process is already "
                         "reproducible (--mode fast), or play it as one: skidsim operator SCRIPT");
  if (mode == "fast" && !player && !replaying)
    throw io::InputError("--mode fast needs a script (--script, or <operator source=\"script\">) or --replay");
  if (!(job.max_s == 0.0 || (job.max_s >= 0.001 && job.max_s <= 86400.0))) throw io::InputError("--max-s: expected 0.001 to 86400 s");
  // LCM: the operator's commands when there is no script; state and events
  // out whenever a provider is named (or the operator is on LCM).
  io::ControlInput input(ex.operator_source.watchdog_s);
  std::unique_ptr<io::LcmBridge> bridge;
  const std::string url = !job.lcm_url.empty() ? job.lcm_url
                          : !ex.operator_source.lcm_url.empty() ? ex.operator_source.lcm_url
                                                                : std::string(io::kDefaultLcmUrl);
  io::LcmChannels channels;
  channels.control = ex.operator_source.channel;
  if ((!player && !replaying) || !job.lcm_url.empty()) bridge = std::make_unique<io::LcmBridge>(url, channels, &input);

  auto world = build_session_world(ex, loader, soils);
  check_tasks(ex, *world);
  SessionTasks tasks(ex, *world);
  StagedRunDirectory run_dir(job.out_dir, "run");
  const std::string log_path = (run_dir.staging() / "session.lcmlog").string();
  auto log_file = std::make_unique<lcm::LogFile>(log_path, "w");
  if (!log_file->good()) throw io::InputError("cannot write the LCM log " + log_path);
  lcm::LogFile& log = *log_file;
  write_session_header(log, identity);  // the first event: which exercise this log belongs to
  if (bridge) bridge->record_controls_to(&log);

  // The optional terrain channel: every tile at the start, then those that
  // changed, every kStepsPerTiles and at the end (so the log rebuilds the
  // final surface).
  std::unique_ptr<TerrainTiles> tiles;
  if (job.terrain_tiles && world->terrain()) tiles = std::make_unique<TerrainTiles>(*world->terrain());
  const auto send_tiles = [&](long step, double t) {
    tiles->send_changed(*world->terrain(), step, t, [&](const skidsim_lcm::terrain_tile_t& m) {
      log_message(log, channels.terrain, m, t);
      if (bridge) bridge->publish_terrain_tile(m);
    });
  };
  // Events to the log and, with a provider, over LCM.
  const auto send_events = [&](long step, double t) {
    for (const SessionEvent& e : tasks.take_events()) {
      skidsim_lcm::event_t m{};
      m.step = step;
      m.sim_time_s = e.time_s;
      m.kind = e.kind;
      m.severity = static_cast<std::int8_t>(e.severity);
      m.text = e.text;
      log_message(log, channels.events, m, t);
      if (bridge) bridge->publish_event(m);
    }
  };
  // Recording: a snapshot of the scene at each frame's time, handed to the
  // recorder's thread.
  std::unique_ptr<FrameRecorder> recorder;
  render::Scene scene;
  SceneHistory scene_history;
  const std::string camera_name = job.camera.empty() ? ex.recording.camera : job.camera;
  const double fps = job.frame_fps > 0.0 ? job.frame_fps : ex.recording.fps;
  const int fw = job.frame_width > 0 ? job.frame_width : ex.recording.width;
  const int fh = job.frame_height > 0 ? job.frame_height : ex.recording.height;
  double next_frame_s = 0.0;
  if (job.record) {
    // Frames are taken between control ticks (100 a second).
    if (!(fps >= 0.1 && fps <= 100.0)) throw io::InputError("--fps: expected 0.1 to 100 frames a second");
    if (fw < 16 || fh < 16 || fw > 8192 || fh > 8192) throw io::InputError("--frame-width / --frame-height: expected 16 to 8192");
    if (job.render_backend != "auto" && job.render_backend != "egl" && job.render_backend != "osmesa")
      throw io::InputError("--render-backend '" + job.render_backend + "': expected auto, egl or osmesa");
    try {
      (void)exercise_camera(camera_name, ex, *world);
    } catch (const std::invalid_argument& e) {
      throw io::InputError(std::string("--camera: ") + e.what());
    }
    std::filesystem::create_directories(run_dir.staging() / "frames");
    scene = static_scene(ex, *world);
    if (world->terrain()) world->terrain()->record_flow(true);  // for the sand's moving texture; the state is untouched
    try {
      recorder = std::make_unique<FrameRecorder>((run_dir.staging() / "frames").string(), fw, fh, job.render_backend);
    } catch (const std::runtime_error& e) {  // no OpenGL: refused before the session starts
      throw io::InputError(std::string("--record: ") + e.what());
    }
  }
  const double limit_s = job.max_s > 0.0 ? job.max_s : ex.time_limit_s;
  Progress progress("run", limit_s);
  vehicle::LoaderControls controls;
  controls.parking_brake = true;
  std::int64_t seq = 0;
  long missed_ticks = 0, missed_in_a_row = 0;
  std::int64_t watchdog_trips_seen = 0;
  std::string end_reason = "time_limit";
  const auto wall_start = std::chrono::steady_clock::now();
  // The report's plots over time (columnar, reserved: no reallocation in the loop).
  const char* const kSeries[] = {"t_s", "chassis_x_m", "chassis_y_m", "speed_m_s", "bucket_payload_kg",
                                 "material_moved_kg", "task_progress", "score", "engine_speed_rpm",
                                 "tipping_margin", "max_wheel_slip"};
  constexpr std::size_t kSeriesCount = sizeof(kSeries) / sizeof(kSeries[0]);
  std::vector<std::vector<double>> timeline(kSeriesCount);
  for (auto& series : timeline) series.reserve(static_cast<std::size_t>(limit_s / (kStepsPerSample * engine::kStepSeconds)) + 2);
  bool script_done_at_set = false;
  double script_done_s = 0.0;
  while (world->time_s() < limit_s) {
    const long step = world->steps();
    const double t = world->time_s();
    if (replaying && replay_end_step >= 0 && step >= replay_end_step) {
      end_reason = "replay_done";
      break;
    }
    if (step % kStepsPerTick == 0) {
      if (jobs::interrupting_signal() != 0) {
        end_reason = "interrupted";
        break;
      }
      skidsim_lcm::state_t state = machine_state(*world, !player && input.neutral());
      state.score = tasks.score();
      state.active_task = tasks.active_task();
      if (replaying) {
        const auto tick = static_cast<std::size_t>(step / kStepsPerTick);
        if (tick >= replay.size()) {
          end_reason = "replay_done";
          break;
        }
        controls = replay[tick];
      } else if (player) {
        controls = player->step(state);
      } else if (mode == "lockstep") {
        // The operator gets this tick's state first and answers with the
        // command stamped for it; the simulator waits for it (up to the
        // watchdog; the first one, while the operator starts, up to 5 s,
        // the state sent again every 100 ms).
        input.await_step(step);
        bridge->publish_state(state);
        const bool first = step == 0;
        const auto start = std::chrono::steady_clock::now();
        const auto deadline =
            start + (first ? std::chrono::milliseconds(5000)
                           : std::chrono::milliseconds(static_cast<int>(1000.0 * ex.operator_source.watchdog_s)));
        auto resend = start + std::chrono::milliseconds(100);
        while (input.last_sim_step() != step && std::chrono::steady_clock::now() < deadline) {
          bridge->wait(5, t);
          if (first && std::chrono::steady_clock::now() > resend) {
            bridge->publish_state(state);
            resend += std::chrono::milliseconds(100);
          }
        }
        if (input.last_sim_step() != step) {
          ++missed_ticks;
          ++missed_in_a_row;
        } else {
          missed_in_a_row = 0;
        }
        controls = input.controls(t);
        // The operator has gone (or finished): a lockstep session cannot go on.
        if (missed_in_a_row >= kMissedTicksToEnd) {
          end_reason = "operator_gone";
          break;
        }
      } else {
        bridge->poll(t);
        controls = input.controls(t);
      }
      skidsim_lcm::control_t applied{};
      applied.seq = ++seq;
      applied.sim_step = step;
      applied.drive_left = controls.drive_left;
      applied.drive_right = controls.drive_right;
      applied.lift = controls.lift;
      applied.tilt = controls.tilt;
      applied.throttle = controls.throttle;
      applied.parking_brake = controls.parking_brake;
      log_message(log, channels.control + "_APPLIED", applied, t);
      tasks.update(*world, kStepsPerTick * engine::kStepSeconds);
      // Spawn events: an agent held for a task comes on site once it is done.
      for (std::size_t k = 0; k < ex.agents.size(); ++k)
        if (!ex.agents[k].start_after.empty() && world->agent_specs()[k].held)
          for (const TaskProgress& p : tasks.tasks())
            if (p.id == ex.agents[k].start_after && p.done) world->release_agent(static_cast<int>(k));
      if (input.stats().watchdog_trips > watchdog_trips_seen) {
        watchdog_trips_seen = input.stats().watchdog_trips;
        tasks.add_event(t, "watchdog", "no command from the operator: levers to neutral, parking brake on", 1);
      }
      send_events(step, t);
      if (tiles && step % kStepsPerTiles == 0) send_tiles(step, t);
      if (recorder && t >= next_frame_s - 1e-9) {
        update_scene(*world, scene, &scene_history);
        recorder->submit(scene, exercise_camera(camera_name, ex, *world));
        next_frame_s += 1.0 / fps;
      }
      if (step % kStepsPerSample == 0) {
        double progress_now = 0.0, worst_slip = 0.0;
        for (const TaskProgress& p : tasks.tasks())
          if (p.id == state.active_task || (state.active_task.empty() && &p == &tasks.tasks().back())) progress_now = p.progress;
        for (double slip : state.wheel_slip) worst_slip = std::max(worst_slip, std::abs(slip));
        const double sample[kSeriesCount] = {t,
                                             state.chassis_position_m[0],
                                             state.chassis_position_m[1],
                                             std::hypot(state.chassis_velocity_m_s[0], state.chassis_velocity_m_s[1]),
                                             state.bucket_payload_kg,
                                             tasks.metrics().material_moved_kg,
                                             progress_now,
                                             tasks.score(),
                                             state.engine_speed_rpm,
                                             state.tipping_margin,
                                             worst_slip};
        for (std::size_t k = 0; k < kSeriesCount; ++k) timeline[k].push_back(sample[k]);
      }
      if (step % kStepsPerState == 0) {
        log_message(log, channels.state, state, t);
        if (bridge && mode != "lockstep") bridge->publish_state(state);
      }
      if (tasks.all_done()) {
        end_reason = "tasks_done";
        break;
      }
      if (player && player->done()) {
        if (!script_done_at_set) {
          script_done_at_set = true;
          script_done_s = t;
        }
        if (t - script_done_s > 1.0) {  // the script has finished: one more second to settle
          end_reason = "script_done";
          break;
        }
      }
    }
    world->step(controls);
    if (mode == "realtime") {
      const auto due = wall_start + std::chrono::duration<double>(world->time_s());
      std::this_thread::sleep_until(due);
    }
    progress.update(world->time_s(), tasks.tasks().empty() ? "" : tasks.tasks().front().detail);
  }
  progress.finish();
  if (tiles) send_tiles(world->steps(), world->time_s());
  json recording = nullptr;
  if (recorder) {
    const std::string recording_error = recorder->finish();
    if (!recording_error.empty()) std::fprintf(stderr, "skidsim: recording stopped: %s (the session is kept)\n", recording_error.c_str());
    recording = {{"frames", recorder->frames_written()}, {"fps", fps}, {"camera", camera_name}, {"dir", "frames"},
                 {"width", fw}, {"height", fh}, {"renderer", recorder->renderer()},
                 {"video", encode_video(run_dir.staging().string(), fps)}, {"error", recording_error}};
  }
  // The end, at the step the world stopped at: a replay stops there too.
  tasks.finish(*world);
  tasks.add_event(world->time_s(), "end", "session ended: " + end_reason, 0);
  send_events(world->steps(), world->time_s());
  const double wall_s = progress.wall_seconds(), sim_s = world->time_s();

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
  for (const io::Metric& m : ex.scoring.metrics) {
    const double value = tasks.metrics().value(m.name);
    breakdown.push_back({{"metric", m.name}, {"weight", m.weight}, {"value", value}, {"points", m.weight * value}});
  }
  // People and trucks: where each ended, and what it was doing.
  json agents = json::array();
  static const char* const kPhases[] = {"not_yet", "moving", "pausing", "docked", "leaving", "gone"};
  for (std::size_t k = 0; k < world->agents().size(); ++k) {
    const engine::AgentState& a = world->agents()[k];
    agents.push_back({{"id", world->agent_specs()[k].id},
                      {"kind", world->agent_specs()[k].kind == engine::AgentKind::kTruck ? "truck" : "person"},
                      {"phase", kPhases[static_cast<int>(a.phase)]},
                      {"docked_at_s", a.docked_at_s},
                      {"position_m", {a.body.position_m.x(), a.body.position_m.y()}}});
  }
  json events = json::array();
  for (const SessionEvent& e : tasks.all_events())
    events.push_back({{"time_s", e.time_s}, {"kind", e.kind}, {"severity", e.severity}, {"text", e.text}});
  json timeline_json = json::object();
  for (std::size_t k = 0; k < kSeriesCount; ++k) timeline_json[kSeries[k]] = timeline[k];
  char hash[32];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(state_hash(*world)));
  const io::ControlStats& cs = input.stats();
  const json report = {
      {"exercise", {{"name", ex.name}, {"file", ex.path}, {"absolute_path", std::filesystem::absolute(ex.path).lexically_normal().string()}}},
      {"mode", mode},
      {"operator", replaying ? "replay " + job.replay_path
                   : player  ? "script " + script_path
                             : "lcm " + url + " channel " + channels.control},
      {"result", {{"passed", tasks.passed()}, {"score", tasks.score()}, {"pass_score", ex.scoring.pass_score},
                  {"all_tasks_done", tasks.all_done()}, {"tasks", task_list}, {"score_breakdown", breakdown},
                  {"script_phases_timed_out", player ? json(player->timed_out()) : json::array()}}},
      {"metrics", metrics},
      {"metrics_not_measured_yet", not_measured},
      {"passes", tasks.metrics().passes},
      {"agents", agents},
      {"peak_bucket_acceleration_m_s2", tasks.metrics().peak_bucket_acceleration_m_s2},
      {"events", events},
      {"timeline", timeline_json},
      {"recording", recording},
      {"controls", {{"accepted", cs.accepted}, {"clamped", cs.clamped}, {"rejected_nan", cs.rejected_nan},
                    {"rejected_stale", cs.rejected_stale}, {"rejected_tick", cs.rejected_tick}, {"malformed", cs.malformed},
                    {"watchdog_trips", cs.watchdog_trips}}},
      {"final_state_hash", hash},
      {"end_reason", end_reason},
      {"lockstep_missed_ticks", missed_ticks},
      {"machine_finite", world->events().finite},
      {"performance", {{"simulated_s", sim_s}, {"wall_time_s", wall_s}, {"real_time_factor", wall_s > 0 ? sim_s / wall_s : 0.0}}},
      {"files", {{"lcm_log", "session.lcmlog"}, {"report_html", "report.html"}, {"terrain", world->terrain() ? "terrain_surface.png" : ""}}},
  };
  if (bridge) bridge->record_controls_to(nullptr);
  log_file.reset();  // closed (flushed) before the run directory is committed
  if (world->terrain())
    io::write_heightmap((run_dir.staging() / "terrain_surface").string(), terrain_snapshot(*world->terrain(), "surface"));
  io::write_text_atomically((run_dir.staging() / "report.json").string(), report.dump(2, ' ', false, json::error_handler_t::replace) + "\n");
  io::write_text_atomically((run_dir.staging() / "report.html").string(), render_report_html(report));
  run_dir.commit();
  std::cout << "session '" << ex.name << "' (" << mode << "): " << (tasks.passed() ? "passed" : "not passed")
            << ", score " << tasks.score() << ", " << sim_s << " s simulated in " << wall_s << " s\n";
  for (const TaskProgress& p : tasks.tasks())
    std::cout << "  task " << p.id << ": " << (p.done ? "done" : "not done") << " (" << p.detail << ")\n";
  std::cout << "wrote " << job.out_dir << "/report.json, report.html, session.lcmlog" << (world->terrain() ? " and the final terrain" : "")
            << "\n";
  return 0;
}

}  // namespace skidsim::apps
