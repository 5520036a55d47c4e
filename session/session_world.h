// A session's world built from its exercise (docs/exercises.md; only what a
// scene needs): firm ground, the soil site with its piles, trenches and
// banks (none for a course on firm ground), obstacles, truck beds, the
// machine at its start; and the machine's state as the LCM state message.
#pragma once

#include <memory>

#include "engine/world.h"
#include "io/exercise.h"
#include "io/soil_table.h"
#include "skidsim_lcm/state_t.hpp"
#include "vehicle/loader_description.h"

namespace skidsim::session {

// Builds the world. Throws io::InputError naming the exercise file for what
// this version cannot build (more than one <soil>).
std::unique_ptr<engine::World> build_session_world(const io::Exercise& exercise,
                                                   const vehicle::LoaderDescription& loader,
                                                   const io::SoilTable& soils);

// The machine's state for the state channel at this step.
skidsim_lcm::state_t machine_state(const engine::World& world, bool controls_neutral);

}  // namespace skidsim::session
