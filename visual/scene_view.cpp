#include "visual/scene_view.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace skidsim::visual {

SceneView::SceneView(const io::Exercise& exercise, const engine::World& world, std::string camera, double fps,
                     SceneStreamReader::Start start)
    : exercise_(exercise),
      camera_(std::move(camera)),
      fps_(fps),
      scene_(static_scene(exercise, world)),
      layout_(capture_layout(world)),
      reader_(start),
      joining_(start == SceneStreamReader::Start::kJoining) {
  (void)exercise_camera(camera_, exercise_, world);  // throws for an unknown camera
  if (!(fps_ > 0.0)) throw std::invalid_argument("fps must be > 0");
  links_ = world.loader().description().links.size();
  trays_ = static_cast<std::size_t>(world.tray_count());
  agents_ = world.agent_specs().size();
  loads_ = trays_ + (world.bucket_material() ? 1u : 0u);
  ground_ = world.terrain() != nullptr;
  SceneFrame initial;
  capture_frame(world, initial);
  ground_nx_ = initial.ground.nx, ground_ny_ = initial.ground.ny;
  for (const FrameField& load : initial.loads) load_sizes_.emplace_back(load.nx, load.ny);
}

int SceneView::apply(const skidsim_lcm::scene_t& message) {
  const auto mismatch = [](const char* what, std::size_t got, std::size_t want) {
    return SceneStreamError("scene: " + std::to_string(got) + " " + what + " where the exercise's world has " + std::to_string(want));
  };
  if (message.link_pose.size() != links_) throw mismatch("links", message.link_pose.size(), links_);
  if (message.tray_pose.size() != trays_) throw mismatch("beds", message.tray_pose.size(), trays_);
  if (message.agent_pose.size() != agents_) throw mismatch("people and trucks", message.agent_pose.size(), agents_);
  if (message.loads.size() != loads_) throw mismatch("loads", message.loads.size(), loads_);
  if (message.has_ground != ground_) throw mismatch("grounds", message.has_ground ? 1u : 0u, ground_ ? 1u : 0u);
  // Sizes too, before the reader makes room for a field (joining, a square
  // may start one).
  const auto sized_as = [](const char* what, int nx, int ny, int want_nx, int want_ny) {
    if (nx != want_nx || ny != want_ny)
      throw SceneStreamError(std::string("scene: ") + what + " of " + std::to_string(nx) + " x " + std::to_string(ny) +
                             " cells where the exercise's world has " + std::to_string(want_nx) + " x " + std::to_string(want_ny));
  };
  if (message.has_ground) sized_as("a ground", message.ground_nx, message.ground_ny, ground_nx_, ground_ny_);
  for (std::size_t k = 0; k < message.loads.size(); ++k)
    sized_as("a load", message.loads[k].nx, message.loads[k].ny, load_sizes_[k].first, load_sizes_[k].second);
  if (!(message.sim_time_s * fps_ < 1e8)) throw SceneStreamError("scene: time " + std::to_string(message.sim_time_s) + " s");
  const bool was_ready = reader_.ready();
  reader_.apply(message);
  if (!reader_.ready()) return 0;
  // Frame k is due at the first message at or after k / fps; joining, the
  // frames due before the picture was whole (or while it was not) are not drawn.
  if (joining_ && !was_ready)
    frames_ = std::max(frames_, static_cast<int>(std::ceil(reader_.frame().time_s * fps_ - 1e-9)));
  int due = 0;
  while (reader_.frame().time_s >= static_cast<double>(frames_ + due) / fps_ - 1e-9) ++due;
  if (due == 0) return 0;
  update_scene(layout_, reader_.frame(), scene_, &history_);
  frame_chassis_ = reader_.frame().links.front();
  frame_time_s_ = reader_.frame().time_s;
  frame_camera_ = exercise_camera(camera_, exercise_, frame_chassis_);
  frames_ += due;
  return due;
}


}  // namespace skidsim::visual
