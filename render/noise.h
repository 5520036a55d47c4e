// Solid noise and turbulence (seed 001, chapter 2): band-limited gradient
// noise on an integer lattice, and turbulence as the sum of its absolute
// value over octaves, each twice the frequency and half the amplitude of
// the last. Dust puffs take their shape from turbulence (a gas's density as
// a power of it) and are carried by it, moved through time by shifting the
// point where it is sampled. Deterministic: the lattice comes from a seed.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>

namespace skidsim::render {

class SolidNoise {
 public:
  explicit SolidNoise(std::uint64_t seed = 1);

  // Gradient noise at p: about -1..1, zero on the lattice points, smooth
  // (the 3 f^2 - 2 f^3 blend between them).
  double noise(const Eigen::Vector3d& p) const;

  // sum_i |noise(2^i p)| / 2^i over `octaves` octaves (the thesis stops
  // where 2^-(k+1) falls below the pixel; the caller knows the pixel).
  double turbulence(const Eigen::Vector3d& p, int octaves) const;

 private:
  static constexpr int kSize = 256;
  std::array<int, 2 * kSize + 2> permutation_{};
  std::array<Eigen::Vector3d, 2 * kSize + 2> gradient_{};
};

}  // namespace skidsim::render
