// Reads a loader: its parameter side file (XML), the URDF it names (urdfdom)
// and the URDF's visual meshes (assimp), into vehicle::LoaderDescription.
// Every problem (malformed URDF, missing or unreadable mesh, a value out of
// range, a cylinder whose stroke cannot reach its joint's range) throws
// InputError naming the file, the line and the element.
#pragma once

#include <string>

#include "vehicle/loader_description.h"

namespace skidsim::io {

vehicle::LoaderDescription load_loader(const std::string& parameters_path);

// assets/loader/skidsteer.params.xml of the assets folder in use.
std::string default_loader_path();

}  // namespace skidsim::io
