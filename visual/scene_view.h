// Frames drawn from the scene stream at a rate (docs/rendering.md, "The
// scene stream"): what `skidsim run --record` and `skidsim view` share, so
// that a view of a session's log draws the session's own recording.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "io/exercise.h"
#include "render/scene.h"
#include "visual/scene_snapshot.h"
#include "visual/scene_stream.h"

namespace skidsim::visual {

class SceneView {
 public:
  // `world` as the exercise builds it (the meshes, the beds' sizes); camera
  // cab, chase, aerial or fixed (std::invalid_argument otherwise); fps > 0.
  // `start`: from the stream's first message (a log), or joining a live
  // stream, whose frames begin once the picture is whole.
  SceneView(const io::Exercise& exercise, const engine::World& world, std::string camera, double fps,
            SceneStreamReader::Start start = SceneStreamReader::Start::kFirstMessage);
  // Applies one message (SceneStreamError as SceneStreamReader::apply, and
  // when its links, beds, agents, loads or ground, or their sizes, are not
  // the world's, or its time beyond 10^8 frames).
  // Returns how many frames are due at it (those due at or before it not
  // yet drawn: one at most at the stream's rate or below); scene() and
  // camera() then show it. Frame k is due at the first message at or after
  // k / fps; joining, the first is the first due once the picture is whole
  // (again, should it stop being whole).
  int apply(const skidsim_lcm::scene_t& message);
  // The last frame due, and the camera that draws it.
  const render::Scene& scene() const { return scene_; }
  const render::Camera& camera() const { return frame_camera_; }
  // Another camera (cab, chase, aerial or fixed; std::invalid_argument
  // otherwise) at the last frame due.
  render::Camera camera(const std::string& name) const { return exercise_camera(name, exercise_, frame_chassis_); }
  // The session's time at the last frame due.
  double frame_time_s() const { return frame_time_s_; }
  // The frames due so far, counted from the stream's time 0 (the next
  // frame's number).
  int frames() const { return frames_; }

 private:
  const io::Exercise& exercise_;
  std::string camera_;
  double fps_;
  render::Scene scene_;
  render::Camera frame_camera_;
  Eigen::Isometry3d frame_chassis_ = Eigen::Isometry3d::Identity();
  double frame_time_s_ = 0.0;
  SceneLayout layout_;
  SceneStreamReader reader_;
  SceneHistory history_;
  int frames_ = 0;
  bool joining_;
  // What the exercise's world has, which every message must match: its
  // counts and its fields' sizes (the ground's, the bucket's, each bed's).
  std::size_t links_ = 0, trays_ = 0, agents_ = 0, loads_ = 0;
  bool ground_ = false;
  int ground_nx_ = 0, ground_ny_ = 0;
  std::vector<std::pair<int, int>> load_sizes_;
};

}  // namespace skidsim::visual
