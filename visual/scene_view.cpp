#include "visual/scene_view.h"

#include <stdexcept>
#include <utility>

namespace skidsim::visual {

SceneView::SceneView(const io::Exercise& exercise, const engine::World& world, std::string camera, double fps)
    : exercise_(exercise), camera_(std::move(camera)), fps_(fps), scene_(static_scene(exercise, world)), layout_(capture_layout(world)) {
  (void)exercise_camera(camera_, exercise_, world);  // throws for an unknown camera
  if (!(fps_ > 0.0)) throw std::invalid_argument("fps must be > 0");
}

int SceneView::apply(const skidsim_lcm::scene_t& message) {
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
