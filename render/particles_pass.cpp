#include "render/particles_pass.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "render/noise.h"

namespace skidsim::render {
namespace {

const char* const kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 centre;
layout(location = 1) in vec2 corner;   // -1..1
layout(location = 2) in vec4 look;     // radius (m), opacity, shape, unused
layout(location = 3) in vec3 colour_in;
uniform mat4 view_projection;
uniform vec3 camera_right;
uniform vec3 camera_up;
out vec2 puff_uv;
out float opacity;
out vec3 colour;
out vec3 world_position;
void main() {
  vec3 p = centre + (corner.x * camera_right + corner.y * camera_up) * look.x;
  world_position = p;
  // One of the atlas's 2 x 2 puffs.
  float k = min(floor(look.z * 4.0), 3.0);
  vec2 cell = vec2(mod(k, 2.0), floor(k / 2.0));
  puff_uv = (cell + corner * 0.5 + 0.5) * 0.5;
  opacity = look.y;
  colour = colour_in;
  gl_Position = view_projection * vec4(p, 1.0);
}
)";

const char* const kFragmentShader = R"(#version 330 core
in vec2 puff_uv;
in float opacity;
in vec3 colour;
in vec3 world_position;
uniform sampler2D puffs;
uniform vec3 sky;
uniform vec3 eye;
out vec4 frag_colour;
void main() {
  float density = texture(puffs, puff_uv).r;
  float a = clamp(density * opacity, 0.0, 1.0);
  if (a < 0.004) discard;
  // Lit from all around (a cloud of grains scatters light every way).
  vec3 c = colour * (0.75 * vec3(1.0, 0.96, 0.9) + 0.35 * sky);
  float haze = 1.0 - exp(-0.004 * length(world_position - eye));
  frag_colour = vec4(mix(c, sky, haze), a);
}
)";

}  // namespace

std::vector<unsigned char> ParticlesPass::make_puff_atlas() {
  const int side = kPuffs * kPuffPixels;
  std::vector<unsigned char> atlas(static_cast<std::size_t>(side) * side, 0);
  const SolidNoise noise(1);
  for (int puff = 0; puff < kPuffs * kPuffs; ++puff) {
    const int x0 = (puff % kPuffs) * kPuffPixels, y0 = (puff / kPuffs) * kPuffPixels;
    for (int y = 0; y < kPuffPixels; ++y)
      for (int x = 0; x < kPuffPixels; ++x) {
        const double u = (x + 0.5) / kPuffPixels * 2.0 - 1.0, v = (y + 0.5) / kPuffPixels * 2.0 - 1.0;
        const double r2 = u * u + v * v;
        if (r2 >= 1.0) continue;
        // Density: turbulence to a power (seed 001's gas), each puff a
        // different slice of the solid space, falling to zero at the rim.
        const double t = noise.turbulence(Eigen::Vector3d(2.5 * u, 2.5 * v, 3.7 * puff + 0.5), 4);
        const double rim = (1.0 - r2) * (1.0 - r2);
        const double density = std::min(1.0, std::pow(std::min(1.0, 1.6 * t), 1.2) * 1.4 + 0.25) * rim;
        atlas[static_cast<std::size_t>(y0 + y) * side + x0 + x] = static_cast<unsigned char>(std::lround(255.0 * density));
      }
  }
  return atlas;
}

ParticlesPass::ParticlesPass(const GlApi& gl) : gl_(gl) {
  program_ = link_program(gl, kVertexShader, kFragmentShader);
  const std::vector<unsigned char> atlas = make_puff_atlas();
  gl.GenTextures(1, &texture_);
  gl.BindTexture(GL_TEXTURE_2D, texture_);
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl.TexImage2D(GL_TEXTURE_2D, 0, GL_R8, kPuffs * kPuffPixels, kPuffs * kPuffPixels, 0, GL_RED, GL_UNSIGNED_BYTE,
                atlas.data());
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl.GenVertexArrays(1, &vao_);
  gl.GenBuffers(1, &vbo_);
  gl.BindVertexArray(vao_);
  gl.BindBuffer(GL_ARRAY_BUFFER, vbo_);
  constexpr GLsizei stride = 12 * sizeof(float);
  gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  gl.VertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(3 * sizeof(float)));
  gl.VertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(5 * sizeof(float)));
  gl.VertexAttribPointer(3, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(9 * sizeof(float)));
  for (GLuint a = 0; a < 4; ++a) gl.EnableVertexAttribArray(a);
}

ParticlesPass::~ParticlesPass() {
  gl_.DeleteBuffers(1, &vbo_);
  gl_.DeleteVertexArrays(1, &vao_);
  gl_.DeleteTextures(1, &texture_);
  gl_.DeleteProgram(program_);
}

void ParticlesPass::draw(const std::vector<Particle>& particles, const Camera& camera, const Eigen::Matrix4f& view_projection,
                         const Eigen::Vector3f& sky, const Eigen::Vector3f& to_sun) {
  (void)to_sun;
  if (particles.empty()) return;
  // Back to front, for blending.
  const Eigen::Vector3f eye = camera.eye_m.cast<float>();
  order_.clear();
  for (std::size_t k = 0; k < particles.size(); ++k)
    order_.emplace_back(-(particles[k].position_m - eye).squaredNorm(), static_cast<int>(k));
  std::sort(order_.begin(), order_.end());
  vertices_.clear();
  static constexpr float kCorners[6][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, -1}, {1, 1}, {-1, 1}};
  for (const auto& [depth, k] : order_) {
    const Particle& p = particles[static_cast<std::size_t>(k)];
    for (const auto& c : kCorners)
      vertices_.insert(vertices_.end(), {p.position_m.x(), p.position_m.y(), p.position_m.z(), c[0], c[1], p.radius_m, p.opacity,
                                         p.shape, 0.0f, p.colour.x(), p.colour.y(), p.colour.z()});
  }
  const Eigen::Vector3d forward = (camera.target_m - camera.eye_m).normalized();
  Eigen::Vector3d right = forward.cross(camera.up);
  if (right.norm() < 1e-9) right = forward.cross(Eigen::Vector3d::UnitY());
  right.normalize();
  const Eigen::Vector3f r = right.cast<float>(), u = right.cross(forward).normalized().cast<float>();
  gl_.UseProgram(program_);
  gl_.UniformMatrix4fv(gl_.GetUniformLocation(program_, "view_projection"), 1, GL_FALSE, view_projection.data());
  gl_.Uniform3fv(gl_.GetUniformLocation(program_, "camera_right"), 1, r.data());
  gl_.Uniform3fv(gl_.GetUniformLocation(program_, "camera_up"), 1, u.data());
  gl_.Uniform3fv(gl_.GetUniformLocation(program_, "sky"), 1, sky.data());
  gl_.Uniform3fv(gl_.GetUniformLocation(program_, "eye"), 1, eye.data());
  gl_.ActiveTexture(GL_TEXTURE1);
  gl_.BindTexture(GL_TEXTURE_2D, texture_);
  gl_.Uniform1i(gl_.GetUniformLocation(program_, "puffs"), 1);
  gl_.BindVertexArray(vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, vbo_);
  gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices_.size() * sizeof(float)), vertices_.data(), GL_STREAM_DRAW);
  gl_.Enable(GL_BLEND);
  gl_.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  gl_.DepthMask(GL_FALSE);
  gl_.DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices_.size() / 12));
  gl_.DepthMask(GL_TRUE);
  gl_.Disable(GL_BLEND);
  gl_.ActiveTexture(GL_TEXTURE0);
}

}  // namespace skidsim::render
