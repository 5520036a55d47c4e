// The renderer's last pass: particles (dust, falling sand) as camera-facing
// discs, blended back to front over the frame without writing depth. Their
// shapes are puffs of turbulence (seed 001: a gas's density is a power of
// turbulence, here fading to nothing at the disc's rim), made once.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "render/gl_api.h"
#include "render/scene.h"

namespace skidsim::render {

class ParticlesPass {
 public:
  explicit ParticlesPass(const GlApi& gl);
  ~ParticlesPass();
  ParticlesPass(const ParticlesPass&) = delete;
  ParticlesPass& operator=(const ParticlesPass&) = delete;

  void draw(const std::vector<Particle>& particles, const Camera& camera, const Eigen::Matrix4f& view_projection,
            const Eigen::Vector3f& sky, const Eigen::Vector3f& to_sun);

  // The puffs' atlas: kPuffs x kPuffs puffs of kPuffPixels square, density 0..255.
  static constexpr int kPuffs = 2, kPuffPixels = 64;
  static std::vector<unsigned char> make_puff_atlas();

 private:
  const GlApi& gl_;
  GLuint program_ = 0, vao_ = 0, vbo_ = 0, texture_ = 0;
  std::vector<float> vertices_;
  std::vector<std::pair<float, int>> order_;
};

}  // namespace skidsim::render
