#include "apps/render_job.h"

#include <chrono>
#include <iostream>

#include "session/session.h"
#include "visual/scene_snapshot.h"
#include "session/session_world.h"
#include "io/atomic_file.h"
#include "io/loader_files.h"
#include "io/png_image.h"
#include "render/renderer.h"

namespace skidsim::apps {

using session::ScriptOperator;
using session::Session;
using session::SessionOptions;
using session::SessionOutput;
using visual::exercise_camera;
using visual::static_scene;

int render_frame(const RenderJob& job) {
  const io::Exercise ex = io::load_exercise(job.exercise_path);
  const vehicle::LoaderDescription loader = io::load_loader(ex.machine.loader);
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  if (!(job.at_s >= 0.0 && job.at_s <= 86400.0)) throw io::InputError("--at-s: expected 0 to 86400 s");
  if (job.at_s > 0.0 && job.script_path.empty()) throw io::InputError("--at-s needs --script (what the operator does until then)");
  const int width = job.width > 0 ? job.width : ex.recording.width;
  const int height = job.height > 0 ? job.height : ex.recording.height;
  io::check_frame_size(width, height, "--width / --height");
  const std::string camera_name = job.camera.empty() ? ex.recording.camera : job.camera;
  // The exercise's world at the start, or after its script has played for
  // --at-s as a session (as skidsim run plays it; a session that ends
  // sooner, its tasks done or its script finished, is drawn as it ended).
  SessionOptions options;
  options.limit_s = job.at_s - 1e-9;
  Session session(ex, loader, soils, options);
  engine::World& world = session.world();
  if (!job.script_path.empty() && job.at_s > 0.0) {
    ScriptOperator script(io::load_operator_script(job.script_path));
    SessionOutput nowhere;
    while (session.tick(false, [&](const skidsim_lcm::state_t& st, long, double t) { return script.decide(st, t); },
                        nowhere)
               .empty()) {
    }
  }
  render::Camera camera;
  try {
    camera = exercise_camera(camera_name, ex, world);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(std::string("--camera: ") + e.what());
  }
  const render::Scene scene = static_scene(ex, world);
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<render::OffscreenContext> context;
  try {
    context = render::make_offscreen_context(job.backend, width, height);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(std::string("--backend: ") + e.what());
  }
  render::Renderer renderer(*context);
  io::RgbImage image;
  image.width = width;
  image.height = height;
  image.rgb = render::render_rgb(*context, renderer, scene, camera);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  io::write_png_rgb8(job.out_path, image);
  std::cout << "rendered '" << ex.name << "' at " << world.time_s() << " s from the " << camera_name << " camera, "
            << width << " x " << height << ", " << render::backend_name(context->backend()) << " ("
            << context->renderer() << "), " << ms << " ms: " << job.out_path << "\n";
  return 0;
}

}  // namespace skidsim::apps
