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
#include <functional>
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
#include "visual/scene_view.h"
#include "session/session.h"
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

using jobs::Progress;
using jobs::StagedRunDirectory;
using jobs::terrain_snapshot;
using report::render_report_html;
using session::DecideControls;
using session::Replay;
using session::ScriptOperator;
using session::Session;
using session::SessionIdentity;
using session::SessionOptions;
using session::SessionOutput;
using session::SessionTasks;
using session::TaskProgress;
using session::TickDecision;
using session::kStepsPerTick;
using session::session_identity;
using session::write_session_header;
using visual::FrameRecorder;
using visual::SceneView;
using visual::encode_video;
namespace {

using nlohmann::json;

// Lockstep: how long a tick waits for the operator's answer before the
// operator counts as gone and the session ends (operator_gone), and how
// often the state is sent again meanwhile (a datagram lost either way is
// asked for again; the operator answers a repeated state with its answer).
// A tick never goes on without its answer: that is what makes a lockstep
// session the same bit for bit however slow the operator or busy the host.
constexpr auto kLockstepAnswerWait = std::chrono::milliseconds(5000);
constexpr auto kLockstepResend = std::chrono::milliseconds(100);

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

// The session's messages into the log and, with a provider, over LCM (the
// state is sent by the lockstep wait itself in that mode).
struct LogAndLcm : SessionOutput {
  lcm::LogFile& log;
  io::LcmBridge* bridge;
  const io::LcmChannels& channels;
  bool publish_state;
  LogAndLcm(lcm::LogFile& l, io::LcmBridge* b, const io::LcmChannels& c, bool p)
      : log(l), bridge(b), channels(c), publish_state(p) {}
  void applied(const skidsim_lcm::control_t& m, double t) override { log_message(log, channels.control + "_APPLIED", m, t); }
  void event(const skidsim_lcm::event_t& m, double t) override {
    log_message(log, channels.events, m, t);
    if (bridge) bridge->publish_event(m);
  }
  void state(const skidsim_lcm::state_t& m, double t) override {
    log_message(log, channels.state, m, t);
    if (bridge && publish_state) bridge->publish_state(m);
  }
  void tile(const skidsim_lcm::terrain_tile_t& m, double t) override {
    log_message(log, channels.terrain, m, t);
    if (bridge) bridge->publish_terrain_tile(m);
  }
  // The scene stream: into the log, over LCM, and to the recording, which
  // draws from it as any view does.
  void scene(const skidsim_lcm::scene_t& m, double t) override {
    log_message(log, channels.scene, m, t);
    if (bridge) bridge->publish_scene(m);
    if (on_scene) on_scene(m);
  }
  std::function<void(const skidsim_lcm::scene_t&)> on_scene;
};

// Recording: the scene stream drawn as skidsim view draws it (the frame due
// at each scene message, 25 a second), handed to the recorder's thread.
class SessionRecording {
 public:
  SessionRecording(const RunJob& job, const io::Exercise& ex, engine::World& world, const std::filesystem::path& staging)
      : camera_(job.camera.empty() ? ex.recording.camera : job.camera),
        fps_(job.frame_fps > 0.0 ? job.frame_fps : ex.recording.fps),
        width_(job.frame_width > 0 ? job.frame_width : ex.recording.width),
        height_(job.frame_height > 0 ? job.frame_height : ex.recording.height) {
    io::check_frame_rate(fps_);
    io::check_frame_size(width_, height_, "--frame-width / --frame-height");
    if (job.render_backend != "auto" && job.render_backend != "egl" && job.render_backend != "osmesa")
      throw io::InputError("--render-backend '" + job.render_backend + "': expected auto, egl or osmesa");
    try {
      view_ = std::make_unique<SceneView>(ex, world, camera_, fps_);
    } catch (const std::invalid_argument& e) {
      throw io::InputError(std::string("--camera: ") + e.what());
    }
    std::filesystem::create_directories(staging / "frames");
    try {
      recorder_ = std::make_unique<FrameRecorder>((staging / "frames").string(), width_, height_, job.render_backend);
    } catch (const std::runtime_error& e) {  // no OpenGL: refused before the session starts
      throw io::InputError(std::string("--record: ") + e.what());
    }
  }
  // Each scene message (25 a second): the frames due, drawn from the stream
  // as skidsim view draws them.
  void on_scene(const skidsim_lcm::scene_t& m) {
    for (int k = view_->apply(m); k > 0; --k) recorder_->submit(view_->scene(), view_->camera());
  }
  // The recorder's last frames written, the video encoded: the report's part.
  json finish(const std::filesystem::path& staging) {
    const std::string error = recorder_->finish();
    if (!error.empty()) std::fprintf(stderr, "skidsim: recording stopped: %s (the session is kept)\n", error.c_str());
    return {{"frames", recorder_->frames_written()}, {"fps", fps_}, {"camera", camera_}, {"dir", "frames"},
            {"width", width_}, {"height", height_}, {"renderer", recorder_->renderer()},
            {"video", encode_video(staging.string(), fps_)}, {"error", error}};
  }

 private:
  std::string camera_;
  double fps_;
  int width_, height_;
  std::unique_ptr<FrameRecorder> recorder_;
  std::unique_ptr<SceneView> view_;
};

// The operator over LCM: the newest valid command (realtime), or the one
// stamped for this tick (lockstep: the operator gets this tick's state first
// and the session waits for its answer, kLockstepAnswerWait at most, sending
// the state again every kLockstepResend; the watchdog plays no part, as
// simulated time stands still while it waits).
class LcmOperator {
 public:
  LcmOperator(io::ControlInput& input, io::LcmBridge& bridge, bool lockstep)
      : input_(input), bridge_(bridge), lockstep_(lockstep) {}
  TickDecision decide(const skidsim_lcm::state_t& state, long step, double t) {
    TickDecision d;
    if (lockstep_) {
      input_.await_step(step);
      bridge_.publish_state(state);
      const auto start = std::chrono::steady_clock::now();
      auto resend = start + kLockstepResend;
      while (input_.last_sim_step() != step && std::chrono::steady_clock::now() < start + kLockstepAnswerWait &&
             jobs::interrupting_signal() == 0) {
        bridge_.wait(5, t);
        if (std::chrono::steady_clock::now() > resend) {
          bridge_.publish_state(state);
          resend = std::chrono::steady_clock::now() + kLockstepResend;  // no burst after a stall
        }
      }
      if (jobs::interrupting_signal() != 0) {
        d.end_now = "interrupted";
      } else if (input_.last_sim_step() != step) {
        // The operator has gone (or finished): a lockstep session cannot go on.
        ++missed_ticks_;
        d.end_now = "operator_gone";
      }
      d.controls = input_.controls(t);
    } else {
      bridge_.poll(t);
      d.controls = input_.controls(t);
    }
    d.watchdog_tripped = input_.stats().watchdog_trips > watchdog_trips_seen_;
    watchdog_trips_seen_ = input_.stats().watchdog_trips;
    return d;
  }
  long missed_ticks() const { return missed_ticks_; }

 private:
  io::ControlInput& input_;
  io::LcmBridge& bridge_;
  bool lockstep_;
  long missed_ticks_ = 0;
  std::int64_t watchdog_trips_seen_ = 0;
};

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
  std::unique_ptr<ScriptOperator> player;
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
  if (!script_path.empty() && !replaying) player = std::make_unique<ScriptOperator>(io::load_operator_script(script_path));
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
  // The log's channels are the base names; a live session's are its own
  // (its name in them), so that sessions on one provider never cross.
  io::LcmChannels channels;
  channels.control = ex.operator_source.channel;
  const bool live_lcm = (!player && !replaying) || !job.lcm_url.empty();
  std::string session_name;
  if (!job.session.empty() && !live_lcm)
    throw io::InputError("--session '" + job.session + "': this run uses no LCM (a script or a replay without --lcm)");
  if (live_lcm) {
    session_name = job.session.empty() ? io::default_session_name(ex.name) : job.session;
    io::check_session_name(session_name, "--session");
    bridge = std::make_unique<io::LcmBridge>(url, io::session_channels(session_name, channels.control), &input);
    std::cout << "live session '" << session_name << "': controls on " << io::session_channels(session_name, channels.control).control
              << ", state on " << io::session_channels(session_name).state << " (" << url << ")" << std::endl;
  }

  SessionOptions options;
  options.limit_s = job.max_s;
  options.stop_at_step = replay_end_step;
  options.terrain_tiles = job.terrain_tiles;
  options.scene_stream = true;
  Session session(ex, loader, soils, options);
  engine::World& world = session.world();
  StagedRunDirectory run_dir(job.out_dir, "run");
  const std::string log_path = (run_dir.staging() / "session.lcmlog").string();
  auto log_file = std::make_unique<lcm::LogFile>(log_path, "w");
  if (!log_file->good()) throw io::InputError("cannot write the LCM log " + log_path);
  lcm::LogFile& log = *log_file;
  write_session_header(log, identity);  // the first event: which exercise this log belongs to
  if (bridge) bridge->record_controls_to(&log);
  LogAndLcm output(log, bridge.get(), channels, mode != "lockstep");

  std::unique_ptr<SessionRecording> recording;
  if (job.record) {
    recording = std::make_unique<SessionRecording>(job, ex, world, run_dir.staging());
    output.on_scene = [&](const skidsim_lcm::scene_t& m) { recording->on_scene(m); };
  }

  // Each tick's controls: a replay's, the script's, or the operator's over LCM.
  std::unique_ptr<LcmOperator> live;
  if (!player && !replaying) live = std::make_unique<LcmOperator>(input, *bridge, mode == "lockstep");
  const DecideControls decide = [&](const skidsim_lcm::state_t& state, long step, double t) {
    TickDecision d;
    if (jobs::interrupting_signal() != 0) {
      d.end_now = "interrupted";
    } else if (replaying) {
      const auto tick = static_cast<std::size_t>(step / kStepsPerTick);
      if (tick >= replay.size()) d.end_now = "replay_done";
      else d.controls = replay[tick];
    } else if (player) {
      d = player->decide(state, t);
    } else {
      d = live->decide(state, step, t);
    }
    return d;
  };

  Progress progress("run", session.limit_s());
  const auto wall_start = std::chrono::steady_clock::now();
  std::string end_reason;
  while (end_reason.empty()) {
    end_reason = session.tick(!player && input.neutral(), decide, output);
    if (mode == "realtime") std::this_thread::sleep_until(wall_start + std::chrono::duration<double>(world.time_s()));
    progress.update(world.time_s(), session.tasks().tasks().empty() ? "" : session.tasks().tasks().front().detail);
  }
  progress.finish();
  const json recorded = recording ? recording->finish(run_dir.staging()) : json(nullptr);
  session.finish(end_reason, output);
  const double wall_s = progress.wall_seconds(), sim_s = world.time_s();
  const SessionTasks& tasks = session.tasks();
  const io::ControlStats& cs = input.stats();
  json report = session.report(end_reason);
  report["mode"] = mode;
  report["operator"] = replaying ? "replay " + job.replay_path
                       : player  ? "script " + script_path
                                 : "lcm " + url + " channel " + io::session_channels(session_name, channels.control).control;
  if (bridge) report["session"] = session_name;
  if (player) report["result"]["script_phases_timed_out"] = player->player().timed_out();
  report["recording"] = recorded;
  report["controls"] = {{"accepted", cs.accepted}, {"clamped", cs.clamped}, {"rejected_nan", cs.rejected_nan},
                        {"rejected_stale", cs.rejected_stale}, {"rejected_tick", cs.rejected_tick}, {"repeated", cs.repeated},
                        {"malformed", cs.malformed}, {"watchdog_trips", cs.watchdog_trips}};
  report["lockstep_missed_ticks"] = live ? live->missed_ticks() : 0;
  report["performance"] = {{"simulated_s", sim_s}, {"wall_time_s", wall_s},
                           {"real_time_factor", wall_s > 0 ? sim_s / wall_s : 0.0}};
  report["files"] = {{"lcm_log", "session.lcmlog"}, {"report_html", "report.html"},
                     {"terrain", world.terrain() ? "terrain_surface.png" : ""}};
  if (bridge) bridge->record_controls_to(nullptr);
  log_file.reset();  // closed (flushed) before the run directory is committed
  if (world.terrain())
    io::write_heightmap((run_dir.staging() / "terrain_surface").string(), terrain_snapshot(*world.terrain(), "surface"));
  io::write_text_atomically((run_dir.staging() / "report.json").string(), report.dump(2, ' ', false, json::error_handler_t::replace) + "\n");
  io::write_text_atomically((run_dir.staging() / "report.html").string(), render_report_html(report));
  run_dir.commit();
  std::cout << "session '" << ex.name << "' (" << mode << "): " << (tasks.passed() ? "passed" : "not passed")
            << ", score " << tasks.score() << ", " << sim_s << " s simulated in " << wall_s << " s\n";
  for (const TaskProgress& p : tasks.tasks())
    std::cout << "  task " << p.id << ": " << (p.done ? "done" : "not done") << " (" << p.detail << ")\n";
  std::cout << "wrote " << job.out_dir << "/report.json, report.html, session.lcmlog" << (world.terrain() ? " and the final terrain" : "")
            << "\n";
  return 0;
}

}  // namespace skidsim::apps
