// Helpers for the loader tests: the shipped machine on flat or sloped firm
// ground, settled.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>

#include "common/physical_constants.h"
#include "engine/world.h"
#include "io/loader_files.h"
#include "io/soil_table.h"

namespace skidsim::testing {

inline const vehicle::LoaderDescription& shipped_loader() {
  static const vehicle::LoaderDescription d = io::load_loader(io::default_loader_path());
  return d;
}

// The soil table's dry sand (flow and terramechanics).
inline const io::SoilRecord& dry_sand() {
  static const io::SoilRecord s = io::load_soil_table(io::default_soil_table_path()).at("dry_sand");
  return s;
}

// Nose-up pitch of the bucket's floor (rad).
inline double bucket_pitch(const engine::World& w) { return std::asin(w.bucket_material()->geometric_up().x()); }

// The operator keeps the bucket's floor at `pitch_rad` with the tilt lever
// (this machine has no self-levelling: raising the arm rolls the bucket back).
inline void hold_pitch(const engine::World& w, double pitch_rad, vehicle::LoaderControls& c, double max_lever = 1.0) {
  c.tilt = std::clamp(6.0 * (bucket_pitch(w) - pitch_rad), -max_lever, max_lever);
}

// Steps for `seconds` of simulated time with fixed controls.
inline void run_for(engine::World& w, const vehicle::LoaderControls& c, double seconds) {
  const long n = std::lround(seconds / engine::kStepSeconds);
  for (long i = 0; i < n; ++i) w.step(c);
}

// The loader on firm ground rising at `slope_rad` along world +x, turned by
// `yaw_rad` about the slope's normal; arm at `lift_rad`, bucket at
// `tilt_rad`; settled for one second with the parking brake on.
inline std::unique_ptr<engine::World> loader_on_ground(double slope_rad = 0.0, double yaw_rad = 0.0,
                                                       double lift_rad = 0.2, double tilt_rad = 0.0,
                                                       engine::FirmGround ground = {}) {
  ground.plane_normal = Eigen::Vector3d(-std::sin(slope_rad), 0.0, std::cos(slope_rad));
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(-slope_rad, Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()))
                      .toRotationMatrix();
  pose.translation() = (shipped_loader().tyre.radius_m - 0.01) * ground.plane_normal;
  auto w = std::make_unique<engine::World>(shipped_loader(), ground, pose, lift_rad, tilt_rad);
  vehicle::LoaderControls brake;
  brake.parking_brake = true;
  run_for(*w, brake, 1.0);
  return w;
}

}  // namespace skidsim::testing
