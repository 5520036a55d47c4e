// Dust and falling sand in the recorded frames (thesis 8.3). The falling
// parcels of the material exchange are drawn as they are (sand in free
// fall, emitted where material leaves a body); dust rises where a parcel
// lands (more and faster the higher it fell), a little where material
// leaves a body, and where the ground's surface slides fast. Each puff is
// carried by turbulent air (seed 001: turbulence sampled at a point that
// drifts through the noise with time), grows and fades. Only the frames
// see it: the simulation is not changed. Deterministic: a generator seeded
// by each frame's step, and the stream's time.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "visual/scene_frame.h"
#include "render/noise.h"
#include "render/scene.h"

namespace skidsim::visual {

// The longest a puff lives (s): a view that joined late draws the dust a
// view of the whole session draws this long after its picture is whole.
inline constexpr double kMaxPuffLifeS = 3.5;

class DustSystem {
 public:
  explicit DustSystem(std::uint64_t seed = 8, std::size_t capacity = 3000);

  // Moves on by dt_s to the frame's present: spawns (parcels landing or
  // leaving a body, the ground's flow in m/s per cell when given), moves,
  // grows and ages every puff.
  void advance(const SceneLayout& layout, const SceneFrame& frame, const std::vector<Eigen::Vector2f>* ground_flow_m_s, double dt_s);

  // Appends the dust's puffs and the falling parcels.
  void append_particles(const SceneLayout& layout, const SceneFrame& frame, std::vector<render::Particle>& out) const;
  std::size_t puffs() const { return puffs_.size(); }

 private:
  struct Puff {
    Eigen::Vector3d position_m, velocity_m_s;
    double age_s = 0.0, life_s = 2.0, radius_m = 0.15, opacity = 0.3;
    float shape = 0.0f;
  };
  double uniform();  // 0..1
  void spawn(const Eigen::Vector3d& at, const Eigen::Vector3d& velocity, double radius_m, double opacity);

  render::SolidNoise noise_;
  std::uint64_t seed_, state_;
  std::size_t capacity_;
  double time_s_ = 0.0;
  double budget_ = 0.0;  // puffs that may still start this frame: kMaxNewPuffsPerS over its time
  std::vector<Puff> puffs_;
};


}  // namespace skidsim::visual
