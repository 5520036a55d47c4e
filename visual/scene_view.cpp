#include "visual/scene_view.h"

#include <stdexcept>
#include <string>
#include <utility>

namespace skidsim::visual {

SceneView::SceneView(const io::Exercise& exercise, const engine::World& world, std::string camera, double fps)
    : exercise_(exercise), camera_(std::move(camera)), fps_(fps), scene_(static_scene(exercise, world)), layout_(capture_layout(world)) {
  (void)exercise_camera(camera_, exercise_, world);  // throws for an unknown camera
  if (!(fps_ > 0.0)) throw std::invalid_argument("fps must be > 0");
  links_ = world.loader().description().links.size();
  trays_ = static_cast<std::size_t>(world.tray_count());
  agents_ = world.agent_specs().size();
  loads_ = trays_ + (world.bucket_material() ? 1u : 0u);
  ground_ = world.terrain() != nullptr;
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
  reader_.apply(message);
  // Frame k is due at the first message at or after k / fps.
  int due = 0;
  while (reader_.frame().time_s >= static_cast<double>(frames_ + due) / fps_ - 1e-9) ++due;
  if (due == 0) return 0;
  update_scene(layout_, reader_.frame(), scene_, &history_);
  frames_ += due;
  return due;
}

render::Camera SceneView::camera() const { return exercise_camera(camera_, exercise_, reader_.frame().links.front()); }

}  // namespace skidsim::visual
