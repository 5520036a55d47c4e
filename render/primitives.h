// Meshes the scene builds from (objects in an exercise are boxes).
#pragma once

#include <cstdint>
#include <utility>

#include "render/scene.h"

namespace skidsim::render {

// A cube from -0.5 to 0.5 on each axis, flat-shaded (a box is this cube
// scaled by the instance's pose), faces counter-clockwise from outside.
inline Mesh unit_cube() {
  Mesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2) {
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[axis] = static_cast<float>(sign);
      const Eigen::Vector3f u = Eigen::Vector3f::Unit((axis + 1) % 3), w = Eigen::Vector3f::Unit((axis + 2) % 3);
      const auto base = static_cast<std::uint32_t>(m.positions_m.size());
      for (const auto& [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
        m.positions_m.push_back(0.5f * (n + static_cast<float>(a) * u + static_cast<float>(b) * w));
        m.normals.push_back(n);
      }
      if (sign > 0) {
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
      } else {
        m.indices.insert(m.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
      }
    }
  return m;
}

}  // namespace skidsim::render
