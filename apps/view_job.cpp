#include "apps/view_job.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
#include "io/json_file.h"
#include "io/lcm_log.h"
#include "io/loader_files.h"
#include "io/run_directory.h"
#include "io/soil_table.h"
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

}  // namespace

int run_view(const ViewJob& job) {
  const fs::path source(job.source);
  const bool run_dir = fs::is_directory(source);
  const fs::path log_path = run_dir ? source / "session.lcmlog" : source;
  const fs::path run = run_dir ? source : source.parent_path();
  const std::string exercise_path = !job.exercise_path.empty() ? job.exercise_path : exercise_of_run(run);
  const io::Exercise ex = io::load_exercise(exercise_path);
  const vehicle::LoaderDescription loader = io::load_loader(ex.machine.loader);
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  const session::SessionIdentity identity = session::session_identity(ex, loader, io::default_soil_table_path());
  const std::vector<io::LcmLogEvent> events = session::load_scene_events(log_path.string(), identity);

  const std::string camera = job.camera.empty() ? ex.recording.camera : job.camera;
  const double fps = job.fps > 0.0 ? job.fps : ex.recording.fps;
  const int width = job.width > 0 ? job.width : ex.recording.width, height = job.height > 0 ? job.height : ex.recording.height;
  if (!(fps >= 0.1 && fps <= io::kMaxRecordFps)) throw io::InputError("--fps: expected 0.1 to 25 frames a second (the scene stream's rate)");
  if (width < 16 || height < 16 || width > 8192 || height > 8192) throw io::InputError("--width / --height: expected 16 to 8192");
  if (job.backend != "auto" && job.backend != "egl" && job.backend != "osmesa")
    throw io::InputError("--backend '" + job.backend + "': expected auto, egl or osmesa");
  // The world as the exercise builds it: its meshes and sizes (it never steps).
  const std::unique_ptr<engine::World> world = session::build_session_world(ex, loader, soils);
  std::unique_ptr<visual::SceneView> view;
  try {
    view = std::make_unique<visual::SceneView>(ex, *world, camera, fps);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(std::string("--camera: ") + e.what());
  }
  const std::string out = !job.out_dir.empty() ? job.out_dir : (run / ("view_" + camera + "_" + fps_text(fps) + "fps")).string();
  io::StagedRunDirectory out_dir(out, "view");
  fs::create_directories(out_dir.staging() / "frames");
  std::unique_ptr<visual::FrameRecorder> recorder;
  try {
    recorder = std::make_unique<visual::FrameRecorder>((out_dir.staging() / "frames").string(), width, height, job.backend);
  } catch (const std::runtime_error& e) {
    throw io::InputError(std::string("view: ") + e.what());
  }
  for (const io::LcmLogEvent& e : events) {
    const std::string where = io::lcm_log_where(log_path.string(), e.data_offset_bytes, e.index);
    try {
      skidsim_lcm::scene_t m;
      visual::decode_scene(e.data.data(), e.data.size(), m);
      for (int k = view->apply(m); k > 0; --k) recorder->submit(view->scene(), view->camera());
    } catch (const visual::SceneStreamError& error) {
      throw io::InputError(where + error.what());
    }
  }
  const std::string error = recorder->finish();
  if (!error.empty()) throw io::InputError("view: drawing stopped: " + error);
  const json meta = {{"frames", recorder->frames_written()}, {"fps", fps}, {"camera", camera}, {"width", width},
                     {"height", height}, {"renderer", recorder->renderer()}, {"log", log_path.string()},
                     {"scene_messages", events.size()}};
  io::write_text_atomically((out_dir.staging() / "frames" / "frames.json").string(), meta.dump(2) + "\n");
  const std::string video = visual::encode_video(out_dir.staging().string(), fps);
  out_dir.commit();
  std::cout << "view: " << recorder->frames_written() << " frames from " << camera << " at " << fps_text(fps) << " fps, drawn from "
            << events.size() << " scene messages of " << log_path.string() << " into " << out << "/frames"
            << (video.empty() ? "" : " (and " + video + ")") << "\n";
  return 0;
}

}  // namespace skidsim::apps
