// Inside io/: the URDF's numbers, checked in its own text before urdfdom
// reads it. urdfdom 3.0 (Debian 12) hands back a mass it cannot parse
// ("nan", "inf", "1e400", "0x10", "450 ") as 0 without a word, so a NaN
// mass came out as "mass 0", and a mass of 1e308 passed to be blamed on
// tyres too soft for the machine. Here every
// number-valued attribute urdfdom reads is parsed by urdfdom's own grammar
// (a plain decimal number) and held to a physical range, and an error names
// the URDF, the line, the link or joint, the element and the attribute.
#pragma once

#include <urdf_model/model.h>
#include <urdf_world/types.h>

#include <map>
#include <string>

namespace skidsim::io {

// Physical ranges of what a loader's URDF may say. Positions and sizes: the
// parameter file's pins are held to +-50 m too (io/loader_files.cpp).
constexpr double kMaxUrdfExtent_m = 50.0;
constexpr double kMinUrdfSize_m = 1.0e-3;        // box sides, cylinder radius and length, sphere radius
constexpr double kMaxUrdfAngle_rad = 7.0;         // a turn either way (2 pi written loosely passes)
constexpr double kMaxUrdfMass_kg = 1.0e5;         // 100 t: far past any skid steer (2.6 t)
constexpr double kMaxUrdfInertia_kg_m2 = 1.0e6;   // 100 t at 3 m
constexpr double kMinUrdfMeshScale = 1.0e-4;      // a mesh in tenths of a millimetre
constexpr double kMaxUrdfMeshScale = 1.0e4;
constexpr double kMaxUrdfEffort = 1.0e7;          // N or N m, joint limits and gains
constexpr double kMaxUrdfVelocity = 1.0e3;        // rad/s or m/s

// Where each <link>/<joint> of the URDF starts, for messages (urdfdom keeps no lines).
struct UrdfLines {
  std::map<std::string, int> link, joint;
};

// Parses `text` (the URDF at `path`, read with read_input_file) with
// tinyxml2, checks its root is <robot> and every number in it as above;
// returns the lines of its links and joints. Throws InputError.
UrdfLines check_urdf_text(const std::string& path, const std::string& text);

struct CheckedUrdf {
  UrdfLines lines;
  urdf::ModelInterfaceSharedPtr model;  // never null
};

// The URDF at `path`: read once (read_input_file, kMaxXmlBytes), its text
// checked (check_urdf_text), then parsed by urdfdom; urdfdom's complaints
// become an InputError with the line of the link or joint they name.
CheckedUrdf read_checked_urdf(const std::string& path);

}  // namespace skidsim::io
