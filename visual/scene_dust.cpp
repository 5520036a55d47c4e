#include "common/physical_constants.h"
#include "visual/scene_dust.h"

#include <algorithm>
#include <cmath>

namespace skidsim::visual {
namespace {

const Eigen::Vector3f kDustColour(0.80f, 0.71f, 0.56f);
const Eigen::Vector3f kFallingSand(0.66f, 0.53f, 0.34f);
// The thesis gives no numbers for its emitters; these are chosen to look
// like a loader's dumping on 2-core software rendering (a few hundred
// puffs at once).
constexpr double kLandingPuffsPerKg = 0.1, kMaxPuffsPerLanding = 4;
constexpr double kMaxNewPuffsPerS = 250;          // a cloud, not a wall: what 2-core llvmpipe draws at 10 fps
constexpr double kSourceChance = 0.25;            // per parcel just off its body, per frame
constexpr double kAvalancheSpeedMS = 0.4;         // ground flow that raises dust
constexpr double kAvalanchePuffsPerCellS = 0.15;  // at that speed and over
constexpr double kAirResponseS = 0.6;             // puffs take up the air's motion
constexpr double kWindMS = 0.45;                  // turbulent air speed scale
constexpr double kNoiseDriftMS = 0.5;             // the noise space's drift (seed 001's animation)

}  // namespace

DustSystem::DustSystem(std::uint64_t seed, std::size_t capacity) : noise_(seed), seed_(seed), state_(seed), capacity_(capacity) {
  puffs_.reserve(capacity);
}

double DustSystem::uniform() {
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return static_cast<double>((z ^ (z >> 31)) >> 11) * (1.0 / 9007199254740992.0);
}

void DustSystem::spawn(const Eigen::Vector3d& at, const Eigen::Vector3d& velocity, double radius_m, double opacity) {
  if (puffs_.size() >= capacity_ || budget_ < 1.0) return;
  budget_ -= 1.0;
  Puff p;
  p.position_m = at;
  p.velocity_m_s = velocity;
  p.radius_m = radius_m;
  p.opacity = opacity;
  p.life_s = 1.8 + (kMaxPuffLifeS - 1.8) * uniform();
  p.shape = static_cast<float>(uniform());
  puffs_.push_back(p);
}

void DustSystem::advance(const SceneLayout& layout, const SceneFrame& frame, const std::vector<Eigen::Vector2f>* ground_flow_m_s,
                         double dt_s) {
  if (!(dt_s > 0.0)) return;
  // The stream's time, a generator drawn afresh from the frame's step, and
  // the frame's own allowance of new puffs (250 a second live 3.5 s at
  // most, far from the capacity): what starts at a frame depends on that
  // frame alone, so a view that joined a live session late draws, once the
  // puffs from before it joined have faded, the dust a view of the whole
  // session draws.
  time_s_ = frame.time_s;
  state_ = seed_ ^ (static_cast<std::uint64_t>(frame.step) * 0xD1B54A32D192ED03ull);
  budget_ = std::min(kMaxNewPuffsPerS * dt_s, kMaxNewPuffsPerS * 0.2);  // this frame's own (0.2 s at most), none saved
  // Parcels about to land raise dust radially, faster and more of it the
  // higher they fell; parcels just off their body raise a little.
  {
    const double quantum_kg = layout.quantum_mass_kg;
    for (const FrameParcel& p : frame.parcels) {
      const double ground = ground_height_m(frame, p.position_m), above = p.position_m.z() - ground;
      const double vz = p.velocity_m_s.z();
      if (vz < 0.0 && above <= -vz * dt_s + 0.02) {
        const double fall_m = vz * vz / (2.0 * kGravity_m_s2) + std::max(0.0, above);
        const double speed = 0.25 * std::sqrt(2.0 * kGravity_m_s2 * fall_m);
        const double kg = static_cast<double>(p.quanta) * quantum_kg;
        const int n = static_cast<int>(std::clamp(kg * kLandingPuffsPerKg * (1.0 + fall_m), 1.0, kMaxPuffsPerLanding));
        for (int k = 0; k < n; ++k) {
          const double a = 2.0 * M_PI * uniform();
          spawn(Eigen::Vector3d(p.position_m.x(), p.position_m.y(), ground + 0.05),
                Eigen::Vector3d(speed * std::cos(a), speed * std::sin(a), 0.3 * speed + 0.1), 0.12 + 0.05 * fall_m, 0.35);
        }
      } else if (vz > -0.6 && uniform() < kSourceChance) {
        const double a = 2.0 * M_PI * uniform();
        spawn(p.position_m, p.velocity_m_s + Eigen::Vector3d(0.2 * std::cos(a), 0.2 * std::sin(a), 0.1), 0.08, 0.2);
      }
    }
  }
  // Fast avalanches on the ground.
  if (ground_flow_m_s && frame.has_ground) {
    const FrameField& g = frame.ground;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const auto c = static_cast<std::size_t>(j) * static_cast<std::size_t>(g.nx) + static_cast<std::size_t>(i);
        const Eigen::Vector2f& v = (*ground_flow_m_s)[c];
        if (v.norm() < kAvalancheSpeedMS || uniform() > kAvalanchePuffsPerCellS * dt_s) continue;
        const Eigen::Vector3d at = g.pose * Eigen::Vector3d(i * g.cell_m, j * g.cell_m, g.surface_m[c] + 0.03);
        spawn(at, Eigen::Vector3d(0.5 * v.x(), 0.5 * v.y(), 0.15), 0.08, 0.2);
      }
  }
  // Move with the turbulent air, grow, fade; the dead go.
  const double take_up = 1.0 - std::exp(-dt_s / kAirResponseS);
  for (Puff& p : puffs_) {
    // The air: turbulence at a point drifting through the noise with time.
    const Eigen::Vector3d q = 0.6 * p.position_m + Eigen::Vector3d(0.0, -kNoiseDriftMS * time_s_, 0.0);
    const Eigen::Vector3d air(kWindMS * (noise_.turbulence(q, 3) - 0.45), kWindMS * (noise_.turbulence(q + Eigen::Vector3d(17.3, 0, 0), 3) - 0.45),
                              0.08 + 0.5 * kWindMS * (noise_.turbulence(q + Eigen::Vector3d(0, 31.7, 0), 3) - 0.45));
    p.velocity_m_s += (air - p.velocity_m_s) * take_up;
    p.position_m += p.velocity_m_s * dt_s;
    p.position_m.z() = std::max(p.position_m.z(), ground_height_m(frame, p.position_m) + 0.02);
    p.radius_m += 0.25 * dt_s;
    p.age_s += dt_s;
  }
  puffs_.erase(std::remove_if(puffs_.begin(), puffs_.end(), [](const Puff& p) { return p.age_s >= p.life_s; }), puffs_.end());
}

void DustSystem::append_particles(const SceneLayout& layout, const SceneFrame& frame, std::vector<render::Particle>& out) const {
  for (const Puff& p : puffs_) {
    const double fade = 1.0 - p.age_s / p.life_s;
    out.push_back({p.position_m.cast<float>(), static_cast<float>(p.radius_m), static_cast<float>(p.opacity * fade * fade), p.shape,
                   kDustColour});
  }
  {
    const double quantum_m3 = layout.quantum_volume_m3;
    int k = 0;
    for (const FrameParcel& p : frame.parcels) {
      const double r = std::clamp(0.6 * std::cbrt(static_cast<double>(p.quanta) * quantum_m3), 0.03, 0.14);
      out.push_back({p.position_m.cast<float>(), static_cast<float>(r), 0.95f, static_cast<float>((k++ % 4) / 4.0 + 0.1),
                     kFallingSand});
    }
  }
}

}  // namespace skidsim::visual
