// The physical and mathematical constants, each once for the whole project
// (header only, no dependencies: terrain/ stays testable with Eigen alone).
#pragma once

namespace skidsim {

inline constexpr double kPi = 3.14159265358979323846;

// Standard gravity (CGPM 1901, the ISO 80000-3 conventional value): one
// gravity for Bullet's world, the loader's weights, the terrain's soil
// mechanics, falling material and the validation experiments.
inline constexpr double kGravity_m_s2 = 9.80665;

inline constexpr double deg_to_rad(double deg) { return deg * kPi / 180.0; }
inline constexpr double rad_to_deg(double rad) { return rad * 180.0 / kPi; }

}  // namespace skidsim
