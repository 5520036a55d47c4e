// Frames drawn from the scene stream at a rate (docs/rendering.md, "The
// scene stream"): what `skidsim run --record` and `skidsim view` share, so
// that a view of a session's log draws the session's own recording.
#pragma once

#include <string>

#include "io/exercise.h"
#include "render/scene.h"
#include "visual/scene_snapshot.h"
#include "visual/scene_stream.h"

namespace skidsim::visual {

class SceneView {
 public:
  // `world` as the exercise builds it (the meshes, the beds' sizes); camera
  // cab, chase, aerial or fixed (std::invalid_argument otherwise); fps > 0.
  SceneView(const io::Exercise& exercise, const engine::World& world, std::string camera, double fps);
  // Applies one message (SceneStreamError as SceneStreamReader::apply, and
  // when its links, beds, agents, loads or ground are not the world's).
  // Returns how many frames are due at it (those due at or before it not
  // yet drawn: one at most at the stream's rate or below); scene() and
  // camera() then show it.
  int apply(const skidsim_lcm::scene_t& message);
  const render::Scene& scene() const { return scene_; }
  render::Camera camera() const;
  int frames() const { return frames_; }

 private:
  const io::Exercise& exercise_;
  std::string camera_;
  double fps_;
  render::Scene scene_;
  SceneLayout layout_;
  SceneStreamReader reader_;
  SceneHistory history_;
  int frames_ = 0;
  // What the exercise's world has, which every message must match.
  std::size_t links_ = 0, trays_ = 0, agents_ = 0, loads_ = 0;
  bool ground_ = false;
};

}  // namespace skidsim::visual
