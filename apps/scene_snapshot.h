// A frame's scene from the world at one instant (render/scene.h): the firm
// ground, the soil site, the material in the bucket and the beds, the
// obstacles and trucks, the machine from its visual meshes; and the
// exercise's cameras. Read between steps; the world is not changed.
#pragma once

#include <string>

#include "engine/world.h"
#include "io/exercise.h"
#include "render/scene.h"

namespace skidsim::apps {

// The parts that do not move (meshes, ground, obstacles, trucks' bodies) and
// the machine's meshes: built once per session.
render::Scene static_scene(const io::Exercise& exercise, const engine::World& world);

// Updates `scene` (from static_scene) to the world's present state: the
// machine's poses, the soil and the material on bodies.
void update_scene(const engine::World& world, render::Scene& scene);

// cab, chase, aerial or fixed (EXERCISES.md); std::invalid_argument for
// another name.
render::Camera exercise_camera(const std::string& name, const io::Exercise& exercise, const engine::World& world);

}  // namespace skidsim::apps
