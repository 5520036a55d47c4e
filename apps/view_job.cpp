#include "apps/view_job.h"

#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <utility>

#include "io/atomic_file.h"
#include "io/json_file.h"
#include "io/lcm_bridge.h"
#include "io/lcm_log.h"
#include "io/loader_files.h"
#include "io/run_directory.h"
#include "io/soil_table.h"
#include "jobs/interrupt.h"
#include "session/session.h"
#include "session/session_replay.h"
#include "session/session_world.h"
#include "visual/frame_recorder.h"
#include "visual/scene_view.h"

namespace skidsim::apps {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// The exercise the run's report.json names (as skidsim review finds it).
std::string exercise_of_run(const fs::path& run) {
  const fs::path report_path = run / "report.json";
  if (!fs::exists(report_path))
    throw io::InputError(report_path.string() + ": not there; name the exercise with --exercise");
  const json report = io::read_json_file(report_path.string(), "JSON file");
  const json& ex = report.contains("exercise") ? report["exercise"] : json();
  for (const char* key : {"absolute_path", "file"})
    if (ex.is_object() && ex.contains(key) && ex[key].is_string() && fs::exists(ex[key].get<std::string>()))
      return ex[key].get<std::string>();
  throw io::InputError(report_path.string() + ": the exercise it names is not there; give it with --exercise");
}

std::string fps_text(double fps) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", fps);
  return text;
}

// What a view draws with: the exercise's world, the view over the stream,
// and per camera a recorder into a staged folder.
struct Drawing {
  io::Exercise exercise;
  std::unique_ptr<engine::World> world;
  double fps = 0.0;
  int width = 0, height = 0;
  std::unique_ptr<visual::SceneView> view;  // drawing from the first camera
  struct Output {
    std::string camera, out;
    std::unique_ptr<io::StagedRunDirectory> out_dir;
    std::unique_ptr<visual::FrameRecorder> recorder;
  };
  std::vector<Output> outputs;
  // The frame due, from every camera (`number`: as FrameRecorder::submit).
  void submit(int number = -1) {
    for (std::size_t k = 0; k < outputs.size(); ++k)
      outputs[k].recorder->submit(view->scene(), k == 0 ? view->camera() : view->camera(outputs[k].camera), number);
  }
};

// --camera: one name, or several separated by commas.
std::vector<std::string> camera_names(const std::string& text, const std::string& exercise_camera) {
  std::vector<std::string> names;
  std::stringstream in(text.empty() ? exercise_camera : text);
  for (std::string name; std::getline(in, name, ',');) {
    if (name.empty() || std::find(names.begin(), names.end(), name) != names.end())
      throw io::InputError("--camera '" + text + "': expected distinct names separated by commas (cab, chase, aerial, fixed)");
    names.push_back(name);
  }
  if (names.empty()) throw io::InputError("--camera: expected a camera");
  return names;
}

// `exercise` and `loader` as loaded (moved into the drawing, which the view
// refers to).
void open_drawing(const ViewJob& job, io::Exercise exercise, const vehicle::LoaderDescription& loader,
                  const std::string& default_out, visual::SceneStreamReader::Start start, Drawing& d) {
  d.exercise = std::move(exercise);
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  const std::vector<std::string> cameras = camera_names(job.camera, d.exercise.recording.camera);
  d.fps = job.fps > 0.0 ? job.fps : d.exercise.recording.fps;
  d.width = job.width > 0 ? job.width : d.exercise.recording.width;
  d.height = job.height > 0 ? job.height : d.exercise.recording.height;
  io::check_frame_rate(d.fps);
  io::check_frame_size(d.width, d.height, "--width / --height");
  if (job.backend != "auto" && job.backend != "egl" && job.backend != "osmesa")
    throw io::InputError("--backend '" + job.backend + "': expected auto, egl or osmesa");
  // The world as the exercise builds it: its meshes and sizes (it never steps).
  d.world = session::build_session_world(d.exercise, loader, soils);
  try {
    d.view = std::make_unique<visual::SceneView>(d.exercise, *d.world, cameras.front(), d.fps, start);
    for (const std::string& name : cameras) (void)d.view->camera(name);  // throws for an unknown camera
  } catch (const std::invalid_argument& e) {
    throw io::InputError(std::string("--camera: ") + e.what());
  }
  for (const std::string& camera : cameras) {
    Drawing::Output o;
    o.camera = camera;
    // --out names the folder, or with several cameras the folders' stem.
    o.out = job.out_dir.empty()     ? default_out + "_" + camera + "_" + fps_text(d.fps) + "fps"
            : cameras.size() == 1 ? job.out_dir
                                  : job.out_dir + "_" + camera;
    o.out_dir = std::make_unique<io::StagedRunDirectory>(o.out, "view");
    fs::create_directories(o.out_dir->staging() / "frames");
    try {
      o.recorder = std::make_unique<visual::FrameRecorder>((o.out_dir->staging() / "frames").string(), d.width, d.height, job.backend);
    } catch (const std::runtime_error& e) {
      throw io::InputError(std::string("view: ") + e.what());
    }
    d.outputs.push_back(std::move(o));
  }
}

// Waits for the frames, writes each camera's frames.json (`meta` and what
// every view says) and a video (`video`: the frames have no gaps), and puts
// the folders in place. Returns where they went, for the summary line.
std::string close_drawing(Drawing& d, const json& meta, bool video) {
  for (Drawing::Output& o : d.outputs) {
    const std::string error = o.recorder->finish();
    if (!error.empty()) throw io::InputError("view: drawing from " + o.camera + " stopped: " + error);
  }
  std::string where;
  for (Drawing::Output& o : d.outputs) {
    json m = meta;
    m.update({{"frames", o.recorder->frames_written()}, {"fps", d.fps}, {"camera", o.camera}, {"width", d.width},
              {"height", d.height}, {"renderer", o.recorder->renderer()}});
    io::write_text_atomically((o.out_dir->staging() / "frames" / "frames.json").string(), m.dump(2) + "\n");
    const std::string name = video ? visual::encode_video(o.out_dir->staging().string(), d.fps) : "";
    o.out_dir->commit();
    where += (where.empty() ? "" : "; ") + std::to_string(o.recorder->frames_written()) + " from " + o.camera + " into " + o.out +
             "/frames" + (name.empty() ? "" : " (and " + name + ")");
  }
  return where;
}

int view_log(const ViewJob& job) {
  const fs::path source(job.source);
  const bool run_dir = fs::is_directory(source);
  const fs::path log_path = run_dir ? source / "session.lcmlog" : source;
  const fs::path run = run_dir ? source : source.parent_path();
  const std::string exercise_path = !job.exercise_path.empty() ? job.exercise_path : exercise_of_run(run);
  // The log is checked whole, against the exercise, before a folder is made.
  io::Exercise ex = io::load_exercise(exercise_path);
  const vehicle::LoaderDescription loader = io::load_loader(ex.machine.loader);
  const session::SessionIdentity identity = session::session_identity(ex, loader, io::default_soil_table_path());
  const std::vector<io::LcmLogEvent> events = session::load_scene_events(log_path.string(), identity);
  Drawing d;
  open_drawing(job, std::move(ex), loader, (run / "view").string(), visual::SceneStreamReader::Start::kFirstMessage, d);
  for (const io::LcmLogEvent& e : events) {
    const std::string where = io::lcm_log_where(log_path.string(), e.data_offset_bytes, e.index);
    try {
      skidsim_lcm::scene_t m;
      visual::decode_scene(e.data.data(), e.data.size(), m);
      for (int k = d.view->apply(m); k > 0; --k) d.submit();
    } catch (const visual::SceneStreamError& error) {
      throw io::InputError(where + error.what());
    }
  }
  const std::string where = close_drawing(d, {{"log", log_path.string()}, {"scene_messages", events.size()}}, true);
  std::cout << "view: frames at " << fps_text(d.fps) << " fps drawn from " << events.size() << " scene messages of "
            << log_path.string() << ": " << where << "\n";
  return 0;
}

// The live stream's messages as they arrive, handed from LCM's thread to
// the view's: the scene's bytes, or that the session ended.
struct Arrival {
  bool end = false;  // the session's "end" event, in turn after its last scene message
  std::vector<std::uint8_t> scene;
};
struct Inbox {
  std::mutex mutex;
  std::condition_variable arrived;
  std::deque<Arrival> queue;
  std::string scene_channel;
  // On LCM's thread, where nothing may escape: an event that does not
  // decode (lcm-gen's decoder throws on some) is not the end.
  void on_message(const lcm::ReceiveBuffer* buffer, const std::string& channel) noexcept {
    try {
      const auto* bytes = static_cast<const std::uint8_t*>(buffer->data);
      Arrival a;
      if (channel == scene_channel) {
        a.scene.assign(bytes, bytes + buffer->data_size);
      } else {
        skidsim_lcm::event_t e;
        if (buffer->data_size > static_cast<std::uint32_t>(INT32_MAX) ||
            e.decode(buffer->data, 0, static_cast<int>(buffer->data_size)) < 0 || e.kind != "end")
          return;
        a.end = true;
      }
      std::lock_guard<std::mutex> lock(mutex);
      queue.push_back(std::move(a));
      arrived.notify_all();
    } catch (const std::exception&) {
    }
  }
};

// A second of the stream refused in a row ends a live view.
constexpr int kRefusedInARow = static_cast<int>(io::kMaxRecordFps);

int view_live(const ViewJob& job) {
  const jobs::InterruptScope interrupt_scope;
  io::check_session_name(job.session, "--session");
  if (job.exercise_path.empty()) throw io::InputError("--exercise: a live view needs the session's exercise file");
  if (!(job.idle_s > 0.0)) throw io::InputError("--idle-s: expected > 0");
  const std::string url = job.lcm_url.empty() ? std::string(io::kDefaultLcmUrl) : job.lcm_url;
  Drawing d;
  io::Exercise ex = io::load_exercise(job.exercise_path);
  const vehicle::LoaderDescription loader = io::load_loader(ex.machine.loader);
  open_drawing(job, std::move(ex), loader, "view_" + job.session, visual::SceneStreamReader::Start::kJoining, d);
  lcm::LCM lcm(url);
  if (!lcm.good()) throw io::InputError("LCM provider '" + url + "' could not be opened");
  const io::LcmChannels channels = io::session_channels(job.session);
  Inbox inbox;
  inbox.scene_channel = channels.scene;
  lcm.subscribe(channels.scene, &Inbox::on_message, &inbox);
  lcm.subscribe(channels.events, &Inbox::on_message, &inbox);
  // LCM's thread: takes messages off the network as they come, whatever
  // the drawing is doing; stopped and joined however this function leaves.
  struct Receiver {
    std::atomic<bool> stop{false};
    std::thread thread;
    ~Receiver() {
      stop = true;
      if (thread.joinable()) thread.join();
    }
  } receiver;
  receiver.thread = std::thread([&] { io::handle_until(lcm, receiver.stop); });
  std::cout << "view: listening to session " << job.session << " on " << url << std::endl;

  // What the view saw: messages taken, refused (first reason), lost (a gap
  // in the session's steps: where), frames drawn and skipped.
  long messages = 0, refused = 0, refused_in_a_row = 0, lost = 0, skipped = 0;
  std::int64_t first_step = -1, last_step = -1;
  std::vector<double> lost_after_s;  // the session's time before each of the first 1000 gaps
  double first_time_s = -1.0, last_time_s = 0.0;
  int first_frame = -1, last_drawn = -1;
  std::string first_refusal, end = "silent";
  // Idle counts from the last message taken (a view may start up to
  // --idle-s before its session).
  auto last_taken = std::chrono::steady_clock::now();
  while (end == "silent") {
    std::deque<Arrival> batch;
    {
      std::unique_lock<std::mutex> lock(inbox.mutex);
      inbox.arrived.wait_for(lock, std::chrono::milliseconds(200), [&] { return !inbox.queue.empty(); });
      batch.swap(inbox.queue);
    }
    if (jobs::interrupting_signal() != 0) {
      end = "interrupted";
      break;
    }
    int due_frame = -1;  // the latest frame due in this batch
    for (const Arrival& a : batch) {
      if (a.end) {
        end = "session_ended";
        break;
      }
      try {
        skidsim_lcm::scene_t m;
        visual::decode_scene(a.scene.data(), a.scene.size(), m);
        const int due = d.view->apply(m);
        refused_in_a_row = 0;
        last_taken = std::chrono::steady_clock::now();
        if (last_step >= 0 && m.step > last_step + session::kStepsPerScene) {
          lost += (m.step - last_step) / session::kStepsPerScene - 1;
          if (lost_after_s.size() < 1000) lost_after_s.push_back(last_time_s);
        }
        if (first_step < 0) first_step = m.step, first_time_s = m.sim_time_s;
        last_step = m.step, last_time_s = m.sim_time_s;
        ++messages;
        if (due == 0) continue;
        if (first_frame < 0) first_frame = d.view->frames() - due;
        if (job.every_frame) {
          for (int k = due; k > 0; --k) d.submit(d.view->frames() - k);
          last_drawn = d.view->frames() - 1;
        } else {
          skipped += (due_frame >= 0 ? 1 : 0) + (due - 1);  // due, and not to be drawn
          due_frame = d.view->frames() - 1;
        }
      } catch (const visual::SceneStreamError& error) {
        // From the network: refused, the frame as it was; squares heal
        // within the stream's refresh. A stream that keeps not fitting (a
        // session started again under the name, another sender) ends the view.
        if (refused++ == 0) first_refusal = error.what();
        if (++refused_in_a_row >= kRefusedInARow) {
          end = "refused";
          break;
        }
      }
    }
    // Behind: only the latest frame due is drawn (the view's state has
    // moved through every one, so the next frames are those a log draws).
    if (due_frame >= 0) {
      d.submit(due_frame);
      last_drawn = due_frame;
    }
    if (end == "silent" && std::chrono::steady_clock::now() - last_taken > std::chrono::duration<double>(job.idle_s)) break;
  }
  receiver.stop = true;
  receiver.thread.join();
  const json meta = {{"session", job.session}, {"lcm_url", url}, {"end", end}, {"scene_messages", messages},
                     {"messages_lost", lost}, {"lost_after_s", lost_after_s}, {"messages_refused", refused},
                     {"first_refusal", first_refusal},
                     {"first_step", first_step}, {"first_time_s", first_time_s}, {"last_step", last_step}, {"first_frame", first_frame},
                     {"last_frame", last_drawn}, {"frames_skipped", skipped}};
  const std::string where = close_drawing(d, meta, first_frame == 0 && skipped == 0);
  std::cout << "view: frames of session " << job.session << " at " << fps_text(d.fps) << " fps (" << skipped << " skipped behind, "
            << lost << " messages lost, " << refused << " refused): " << where << "\n";
  if (!first_refusal.empty()) std::cerr << "skidsim view: first refused: " << first_refusal << "\n";
  if (end == "interrupted") throw jobs::Interrupted("view interrupted; the frames drawn are kept", jobs::interrupting_signal());
  if (end == "silent") {
    std::cerr << "skidsim view: no scene from session " << job.session << " for " << job.idle_s << " s; stopping\n";
    return 1;
  }
  if (end == "refused") {
    std::cerr << "skidsim view: " << kRefusedInARow << " scene messages in a row did not fit; stopping\n";
    return 1;
  }
  return 0;
}

}  // namespace

int run_view(const ViewJob& job) {
  if (job.session.empty() == job.source.empty())
    throw io::InputError("view: give a run directory (or a session.lcmlog), or --session NAME for a live session; not both");
  return job.session.empty() ? view_log(job) : view_live(job);
}

}  // namespace skidsim::apps
