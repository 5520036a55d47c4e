// A rigid body that only translates, integrated the way SoilContactModel's
// BodyReaction asks an engine to: the soil's vertical force implicitly
// (its stiffness and damping), shear and wedge forces as bounded reactions.
// Enough for plates, blocks, wheels and blades on the soil without a
// multibody engine: the terrain tests and the speed-against-error report
// (apps/perf_ladders*.cpp) use it.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

#include "terrain/soil_contact.h"

namespace skidsim::terrain {

struct TranslatingBody {
  double mass_kg = 1000.0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();

  BodyMotion motion() const {
    BodyMotion m;
    m.reference_point_m = position_m;
    m.linear_velocity_m_s = velocity_m_s;
    return m;
  }

  // One step of length dt under the soil's reaction and an external force
  // (gravity included by the caller).
  void step(const BodyReaction& r, const Eigen::Vector3d& external_N, double dt) {
    const double k = r.normal_stiffness_N_per_m, c = r.normal_damping_N_s_per_m;
    const double vz = velocity_m_s.z();
    velocity_m_s.z() = (mass_kg * vz + dt * (r.force_N.z() + c * vz + external_N.z())) / (mass_kg + dt * (dt * k + c));
    // Horizontal: free motion, then the bounded reactions take back as much
    // of it as their bounds allow (shear both ways, each wedge against
    // motion towards it).
    for (int axis = 0; axis < 2; ++axis) {
      const double v_free = velocity_m_s[axis] + dt * (r.force_N[axis] + external_N[axis]) / mass_kg;
      const double resist_plus = r.shear_bound_N + r.wedge[2 * axis].bound_N;
      const double resist_minus = r.shear_bound_N + r.wedge[2 * axis + 1].bound_N;
      const double impulse = std::clamp(-mass_kg * v_free, -resist_plus * dt, resist_minus * dt);
      velocity_m_s[axis] = v_free + impulse / mass_kg;
    }
    position_m += dt * velocity_m_s;
  }
};

}  // namespace skidsim::terrain
