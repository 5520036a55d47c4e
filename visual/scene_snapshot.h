// A frame's scene from the world at one instant (render/scene.h): the firm
// ground, the soil site, the material in the bucket and the beds, the
// obstacles and trucks, the machine from its visual meshes; and the
// exercise's cameras. Read between steps; the world is not changed.
#pragma once

#include <string>

#include "visual/scene_dust.h"
#include "visual/scene_frame.h"
#include "engine/world.h"
#include "io/exercise.h"
#include "render/scene.h"

namespace skidsim::visual {

// The parts that do not move (meshes, ground, obstacles, trucks' bodies) and
// the machine's meshes: built once per session.
render::Scene static_scene(const io::Exercise& exercise, const engine::World& world);

// What a recording carries from one frame to the next: the soil's flow
// record at the last frame (flow speeds come from its change) and the dust.
struct SceneHistory {
  double time_s = -1.0;
  std::vector<std::int64_t> flow_x, flow_y;
  DustSystem dust;
  SceneFrame frame;  // update_scene(world, ...)'s capture, its buffers kept
};

// The speed of the ground's sliding surface layer per cell (m/s) from the
// quanta its avalanches sent across each face in dt_s (the grid's flow
// record): the volume flux per unit width over the flowing layer's depth.
// The depth of a sliding sand layer, a few dozen grains:
inline constexpr double kFlowingLayerM = 0.03;

// Updates `scene` (from static_scene) to a frame: the
// machine's poses, the soil and the material on bodies, the falling
// parcels; with a history (a recording: frames in time order), the soil's
// flow for its moving texture and the dust.
void update_scene(const SceneLayout& layout, const SceneFrame& frame, render::Scene& scene, SceneHistory* history = nullptr);
// The same for the world's present (capture_layout, capture_frame).
void update_scene(const engine::World& world, render::Scene& scene, SceneHistory* history = nullptr);

// cab, chase, aerial or fixed (docs/rendering.md, "Cameras"); std::invalid_argument
// for another name.
render::Camera exercise_camera(const std::string& name, const io::Exercise& exercise, const engine::World& world);
// The same from the chassis' pose (a frame's first link).
render::Camera exercise_camera(const std::string& name, const io::Exercise& exercise, const Eigen::Isometry3d& chassis);

}  // namespace skidsim::visual
