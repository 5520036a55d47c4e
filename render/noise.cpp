#include "render/noise.h"

#include <cmath>
#include <utility>

namespace skidsim::render {
namespace {

std::uint64_t split_mix(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double unit(std::uint64_t& state) { return static_cast<double>(split_mix(state) >> 11) * (1.0 / 9007199254740992.0); }

double s_curve(double f) { return f * f * (3.0 - 2.0 * f); }

}  // namespace

SolidNoise::SolidNoise(std::uint64_t seed) {
  std::uint64_t state = seed;
  // Unit gradients, uniform over directions: components in [-1, 1],
  // rejected outside the unit ball, normalised.
  for (int i = 0; i < kSize; ++i) {
    Eigen::Vector3d g;
    do {
      g = Eigen::Vector3d(2.0 * unit(state) - 1.0, 2.0 * unit(state) - 1.0, 2.0 * unit(state) - 1.0);
    } while (g.squaredNorm() > 1.0 || g.squaredNorm() < 1e-6);
    gradient_[static_cast<std::size_t>(i)] = g.normalized();
    permutation_[static_cast<std::size_t>(i)] = i;
  }
  for (int i = kSize - 1; i > 0; --i)
    std::swap(permutation_[static_cast<std::size_t>(i)], permutation_[split_mix(state) % static_cast<std::uint64_t>(i + 1)]);
  // Doubled tables: p[p[i] + j] + k needs no modulo.
  for (int i = 0; i < kSize + 2; ++i) {
    permutation_[static_cast<std::size_t>(kSize + i)] = permutation_[static_cast<std::size_t>(i % kSize)];
    gradient_[static_cast<std::size_t>(kSize + i)] = gradient_[static_cast<std::size_t>(i % kSize)];
  }
}

double SolidNoise::noise(const Eigen::Vector3d& p) const {
  int b0[3], b1[3];
  double r0[3], s[3];
  for (int a = 0; a < 3; ++a) {
    const double t = p[a] + 4096.0;  // keep negative coordinates on the lattice's positive side
    const double cell = std::floor(t);
    b0[a] = static_cast<int>(static_cast<std::int64_t>(cell) & (kSize - 1));
    b1[a] = (b0[a] + 1) & (kSize - 1);
    r0[a] = t - cell;
    s[a] = s_curve(r0[a]);
  }
  const auto corner = [&](int cx, int cy, int cz) {
    const int i = cx ? b1[0] : b0[0], j = cy ? b1[1] : b0[1], k = cz ? b1[2] : b0[2];
    const Eigen::Vector3d& g = gradient_[static_cast<std::size_t>(
        permutation_[static_cast<std::size_t>(permutation_[static_cast<std::size_t>(i)] + j)] + k)];
    return g.dot(Eigen::Vector3d(r0[0] - cx, r0[1] - cy, r0[2] - cz));
  };
  const auto lerp = [](double t, double a, double b) { return a + t * (b - a); };
  const double x00 = lerp(s[0], corner(0, 0, 0), corner(1, 0, 0)), x10 = lerp(s[0], corner(0, 1, 0), corner(1, 1, 0));
  const double x01 = lerp(s[0], corner(0, 0, 1), corner(1, 0, 1)), x11 = lerp(s[0], corner(0, 1, 1), corner(1, 1, 1));
  return 1.5 * lerp(s[2], lerp(s[1], x00, x10), lerp(s[1], x01, x11));
}

double SolidNoise::turbulence(const Eigen::Vector3d& p, int octaves) const {
  double sum = 0.0, scale = 1.0;
  for (int i = 0; i < octaves; ++i, scale *= 2.0) sum += std::abs(noise(scale * p)) / scale;
  return sum;
}

}  // namespace skidsim::render
