#include "render/renderer.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "render/particles_pass.h"
#include "render/terrain_mesh.h"

namespace skidsim::render {
namespace {


const char* const kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 flow_a;  // velocity (m/s), layer 0's displacement (m)
layout(location = 3) in vec4 flow_b;  // layers 1 and 2's displacements (m)
uniform mat4 model;
uniform mat4 view_projection;
uniform mat4 sun_view_projection;
uniform float shadow_offset_m;
out vec3 world_position;
out vec3 world_normal;
out vec4 sun_position;
out vec2 flow_velocity;
out vec2 displacement[3];
void main() {
  vec4 p = model * vec4(position, 1.0);
  world_position = p.xyz;
  flow_velocity = flow_a.xy;
  displacement[0] = flow_a.zw;
  displacement[1] = flow_b.xy;
  displacement[2] = flow_b.zw;
  world_normal = mat3(model) * normal;  // rigid poses: no scaling
  // Looked up in the sun's map from a little off the surface (normal
  // offset, about a texel and a half): no self-shadowing speckle where the
  // sun grazes a face.
  sun_position = sun_view_projection * vec4(p.xyz + normalize(world_normal) * shadow_offset_m, 1.0);
  gl_Position = view_projection * p;
}
)";

const char* const kFragmentShader = R"(#version 330 core
in vec3 world_position;
in vec3 world_normal;
in vec4 sun_position;
in vec2 flow_velocity;
in vec2 displacement[3];
uniform float flow_time_s;    // simulated time modulo the period (float keeps its precision)
uniform float flow_phase_s;   // sigma
uniform float flow_period_s;  // tau
uniform vec3 colour;
uniform vec3 to_sun;
uniform vec3 sky;
uniform vec3 eye;
uniform float grain;  // 1 for sand: a pattern fixed to the world
uniform sampler2D sun_depth;
out vec4 frag_colour;
float hash(vec2 p) { return fract(sin(dot(p, vec2(127.1, 311.7))) * 43758.5453); }
float sand_grain(vec2 p) { return hash(floor(p * 40.0)) * 0.6 + hash(floor(p * 9.0)) * 0.4; }
// Sliding sand (thesis 8.2.3): three copies of the texture, each moved
// along with the flow and put back (displacement zero) once every period
// tau, at the instant its weight is zero; the weights, a third of a period
// apart, always sum to one. The copies share one base coordinate, so sand
// at rest (no displacement) looks the same whatever the weights.
float flowing_grain(vec2 p) {
  const float two_pi = 6.28318530718;
  float t = flow_time_s, sigma = flow_phase_s, tau = flow_period_s;
  float w0 = (1.0 - cos(two_pi * (t + sigma) / tau)) / 3.0;
  float w1 = (1.0 - cos(two_pi * t / tau)) / 3.0;
  float w2 = (1.0 - cos(two_pi * (t - sigma) / tau)) / 3.0;
  return w0 * sand_grain(p - displacement[0]) + w1 * sand_grain(p - displacement[1]) + w2 * sand_grain(p - displacement[2]);
}
float lit_by_sun(vec3 n) {
  vec3 p = sun_position.xyz / sun_position.w * 0.5 + 0.5;
  if (p.x < 0.0 || p.x > 1.0 || p.y < 0.0 || p.y > 1.0 || p.z > 1.0) return 1.0;
  float bias = 0.0015 + 0.003 * (1.0 - max(dot(n, to_sun), 0.0));
  vec2 texel = 1.0 / vec2(textureSize(sun_depth, 0));
  // Percentage-closer filtering over 2 x 2 taps half a texel apart.
  float lit = 0.0;
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y)
      lit += p.z - bias > texture(sun_depth, p.xy + (vec2(x, y) - 0.5) * texel).r ? 0.0 : 1.0;
  return lit / 4.0;
}
void main() {
  vec3 n = normalize(world_normal);
  // A surface seen from behind (a height field from below) is lit as its
  // other side; by the normal, not gl_FrontFacing, so a mesh's winding
  // does not matter.
  if (dot(n, eye - world_position) < 0.0) n = -n;
  vec3 base = colour;
  if (grain > 0.5) {
    bool moved = dot(flow_velocity, flow_velocity) + dot(displacement[0], displacement[0]) +
                 dot(displacement[1], displacement[1]) + dot(displacement[2], displacement[2]) > 0.0;
    float g = moved ? flowing_grain(world_position.xy) : sand_grain(world_position.xy);
    base *= 0.88 + 0.2 * g;
  }
  float sun = max(dot(n, to_sun), 0.0) * lit_by_sun(n);
  float skylight = 0.5 + 0.5 * n.z;
  vec3 c = base * (0.75 * sun * vec3(1.0, 0.96, 0.9) + 0.45 * skylight * sky);
  float haze = 1.0 - exp(-0.004 * length(world_position - eye));
  frag_colour = vec4(mix(c, sky, haze), 1.0);
}
)";

const char* const kDepthVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 model;
uniform mat4 sun_view_projection;
void main() { gl_Position = sun_view_projection * model * vec4(position, 1.0); }
)";

const char* const kDepthFragmentShader = R"(#version 330 core
void main() {}
)";

Eigen::Matrix4f look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  const Eigen::Vector3d f = (target - eye).normalized();
  Eigen::Vector3d s = f.cross(up);
  if (s.norm() < 1e-9) s = f.cross(Eigen::Vector3d::UnitY());
  s.normalize();
  const Eigen::Vector3d u = s.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m.cast<float>();
}

Eigen::Matrix4f perspective(double fov_y_deg, double aspect, double near_m, double far_m) {
  const double t = 1.0 / std::tan(0.5 * fov_y_deg * kPi / 180.0);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (far_m + near_m) / (near_m - far_m);
  m(2, 3) = 2.0 * far_m * near_m / (near_m - far_m);
  m(3, 2) = -1.0;
  return m.cast<float>();
}

Eigen::Matrix4f orthographic(const Eigen::AlignedBox3d& box) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int k = 0; k < 3; ++k) {
    m(k, k) = 2.0 / (box.max()[k] - box.min()[k]);
    m(k, 3) = -(box.max()[k] + box.min()[k]) / (box.max()[k] - box.min()[k]);
  }
  return m.cast<float>();
}

// The sun's view: looking along its direction at the centre of the bounds,
// an orthographic box around their corners.
Eigen::Matrix4f sun_view_projection(const Scene& scene) {
  const Eigen::Vector3d d = scene.sun_direction.normalized();
  const Eigen::Vector3d centre = scene.shadow_bounds_m.center();
  const double reach = scene.shadow_bounds_m.sizes().norm();
  const Eigen::Matrix4f view = look_at(centre - reach * d, centre, std::abs(d.z()) > 0.99 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ());
  Eigen::AlignedBox3d box;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector4f c = view * scene.shadow_bounds_m.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)).cast<float>().homogeneous();
    box.extend(c.head<3>().cast<double>());
  }
  // View space looks down -z: near and far are the box's -max and -min z.
  const Eigen::AlignedBox3d volume(Eigen::Vector3d(box.min().x(), box.min().y(), -box.max().z() - 1.0),
                                   Eigen::Vector3d(box.max().x(), box.max().y(), -box.min().z() + 1.0));
  Eigen::Matrix4f flip = Eigen::Matrix4f::Identity();
  flip(2, 2) = -1.0f;
  return orthographic(volume) * flip * view;
}

}  // namespace

// A mesh on the GPU: positions and normals interleaved, indices.
struct GpuMesh {
  GLuint vao = 0, vbo = 0, ibo = 0;
  std::size_t vertices = 0, indices = 0;
};

// A height field as last drawn: its heights and mask, its mesh here and on
// the GPU. A new frame updates only the rows whose heights changed.
struct FieldCache {
  int nx = 0, ny = 0;
  std::vector<float> height_m;
  std::vector<std::uint8_t> shows;
  std::size_t skirt_vertices = 0;
  Mesh mesh;
  GpuMesh gpu;
  // The flow texture's state (8.2): per vertex the velocity and the three
  // layers' displacements, 8 floats, in a buffer of their own.
  GLuint flow_vbo = 0;
  std::vector<float> flow;
  double flow_time_s = std::numeric_limits<double>::quiet_NaN();
  bool flow_on_gpu_nonzero = false;
};

struct Renderer::Gpu {
  GLuint program = 0, depth_program = 0;
  GLuint shadow_fbo = 0, shadow_texture = 0;
  std::vector<GpuMesh> meshes;     // by Scene::meshes index
  std::vector<FieldCache> fields;  // by Scene::fields index
  std::vector<float> interleaved;  // scratch
  std::unique_ptr<ParticlesPass> particles;
};

namespace {

// Vertices [first, end) of the mesh, positions and normals interleaved.
void interleave(const Mesh& mesh, std::size_t first, std::size_t end, std::vector<float>& interleaved) {
  interleaved.resize((end - first) * 6);
  for (std::size_t v = first; v < end; ++v) {
    float* out = &interleaved[6 * (v - first)];
    for (int k = 0; k < 3; ++k) {
      out[k] = mesh.positions_m[v][k];
      out[3 + k] = v < mesh.normals.size() ? mesh.normals[v][k] : (k == 2 ? 1.0f : 0.0f);
    }
  }
}

void upload(const GlApi& gl, const Mesh& mesh, GpuMesh& g, std::vector<float>& interleaved) {
  if (!g.vao) {
    gl.GenVertexArrays(1, &g.vao);
    gl.GenBuffers(1, &g.vbo);
    gl.GenBuffers(1, &g.ibo);
  }
  interleave(mesh, 0, mesh.positions_m.size(), interleaved);
  gl.BindVertexArray(g.vao);
  gl.BindBuffer(GL_ARRAY_BUFFER, g.vbo);
  gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)), interleaved.data(),
                GL_DYNAMIC_DRAW);
  gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo);
  gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)),
                mesh.indices.data(), GL_DYNAMIC_DRAW);
  gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  gl.EnableVertexAttribArray(0);
  gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
  gl.EnableVertexAttribArray(1);
  g.vertices = mesh.positions_m.size();
  g.indices = mesh.indices.size();
}

// A field's mesh brought up to date: rebuilt when its size or mask changed,
// otherwise updated over the rectangle of cells whose heights changed, and
// only those rows (and the index buffer, if a diagonal flipped) uploaded.
void update_field(const GlApi& gl, const HeightField& f, FieldCache& c, std::vector<float>& interleaved) {
  if (!c.gpu.vao || c.nx != f.nx || c.ny != f.ny || c.shows != f.shows || c.skirt_vertices != skirt_vertex_count(f)) {
    build_terrain_mesh(f, c.mesh);
    upload(gl, c.mesh, c.gpu, interleaved);
    if (c.flow_vbo) {  // sized for the old mesh: advance_flow makes it anew
      gl.DeleteBuffers(1, &c.flow_vbo);
      c.flow_vbo = 0;
    }
    c.nx = f.nx;
    c.ny = f.ny;
    c.height_m = f.height_m;
    c.shows = f.shows;
    c.skirt_vertices = skirt_vertex_count(f);
    return;
  }
  int i0 = f.nx, j0 = f.ny, i1 = 0, j1 = 0;
  for (int j = 0; j < f.ny; ++j) {
    const float* now = &f.height_m[static_cast<std::size_t>(j) * f.nx];
    const float* was = &c.height_m[static_cast<std::size_t>(j) * f.nx];
    for (int i = 0; i < f.nx; ++i)
      if (now[i] != was[i]) {
        i0 = std::min(i0, i);
        i1 = std::max(i1, i + 1);
        j0 = std::min(j0, j);
        j1 = j + 1;
      }
  }
  if (i1 == 0) return;
  const bool flipped = update_terrain_mesh(f, i0, j0, i1, j1, c.mesh);
  for (int j = j0; j < j1; ++j)
    std::copy_n(&f.height_m[static_cast<std::size_t>(j) * f.nx + i0], i1 - i0, &c.height_m[static_cast<std::size_t>(j) * f.nx + i0]);
  const std::size_t first = static_cast<std::size_t>(std::max(0, j0 - 1)) * f.nx;
  const std::size_t end = static_cast<std::size_t>(std::min(f.ny, j1 + 1)) * f.nx;
  interleave(c.mesh, first, end, interleaved);
  gl.BindVertexArray(c.gpu.vao);
  gl.BindBuffer(GL_ARRAY_BUFFER, c.gpu.vbo);
  gl.BufferSubData(GL_ARRAY_BUFFER, static_cast<GLintptr>(first * 6 * sizeof(float)),
                   static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)), interleaved.data());
  if (skirt_vertex_count(f) > 0 && (i0 <= 1 || j0 <= 1 || i1 >= f.nx - 1 || j1 >= f.ny - 1)) {
    const std::size_t skirt = static_cast<std::size_t>(f.nx) * f.ny;
    interleave(c.mesh, skirt, c.mesh.positions_m.size(), interleaved);
    gl.BufferSubData(GL_ARRAY_BUFFER, static_cast<GLintptr>(skirt * 6 * sizeof(float)),
                     static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)), interleaved.data());
  }
  if (flipped) {
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, c.gpu.ibo);
    gl.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(c.mesh.indices.size() * sizeof(std::uint32_t)),
                     c.mesh.indices.data());
  }
}

// Moves each layer's displacement on by velocity x time, and puts a layer
// back where its weight passes zero (t = t0 + k tau), moved on since then.
constexpr double kFlowPhaseS = 0.3;  // sigma of 8.2.3 (tau: kFlowPeriodS)

void advance_flow(const GlApi& gl, const HeightField& f, FieldCache& c, double t_s) {
  const std::size_t n = c.mesh.positions_m.size(), cells = static_cast<std::size_t>(f.nx) * f.ny;
  if (!c.flow_vbo) {
    gl.GenBuffers(1, &c.flow_vbo);
    c.flow.assign(8 * n, 0.0f);
    gl.BindVertexArray(c.gpu.vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, c.flow_vbo);
    gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(c.flow.size() * sizeof(float)), c.flow.data(), GL_DYNAMIC_DRAW);
    gl.VertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, 8 * sizeof(float), nullptr);
    gl.EnableVertexAttribArray(2);
    gl.VertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, 8 * sizeof(float), reinterpret_cast<void*>(4 * sizeof(float)));
    gl.EnableVertexAttribArray(3);
    c.flow_time_s = t_s;
  }
  double dt = t_s - c.flow_time_s;
  if (!(dt >= 0.0 && dt < 10.0)) {  // a jump in time (a new session, a seek): start afresh
    std::fill(c.flow.begin(), c.flow.end(), 0.0f);
    dt = 0.0;
  }
  bool any = false;
  const bool has_flow = f.flow_m_s.size() == cells;
  if (!has_flow && !c.flow_on_gpu_nonzero && dt > 0.0) {  // at rest, and all put back already
    c.flow_time_s = t_s;
    return;
  }
  for (std::size_t v = 0; v < cells; ++v) {
    float* x = &c.flow[8 * v];
    const Eigen::Vector2f vel = has_flow ? f.flow_m_s[v] : Eigen::Vector2f::Zero();
    x[0] = vel.x();
    x[1] = vel.y();
    for (int layer = 0; layer < 3; ++layer) {
      x[2 + 2 * layer] += static_cast<float>(vel.x() * dt);
      x[3 + 2 * layer] += static_cast<float>(vel.y() * dt);
    }
    any = any || x[0] != 0.0f || x[1] != 0.0f || x[2] != 0.0f || x[3] != 0.0f || x[4] != 0.0f || x[5] != 0.0f ||
          x[6] != 0.0f || x[7] != 0.0f;
  }
  for (int layer = 0; layer < 3; ++layer) {
    const double t0 = (layer - 1) * kFlowPhaseS;
    const double k_now = std::floor((t_s - t0) / kFlowPeriodS);
    if (k_now <= std::floor((c.flow_time_s - t0) / kFlowPeriodS) && dt > 0.0) continue;
    const auto since = static_cast<float>(t_s - (t0 + k_now * kFlowPeriodS));
    for (std::size_t v = 0; v < cells; ++v) {
      c.flow[8 * v + 2 + 2 * layer] = c.flow[8 * v] * since;
      c.flow[8 * v + 3 + 2 * layer] = c.flow[8 * v + 1] * since;
    }
  }
  c.flow_time_s = t_s;
  if (any || c.flow_on_gpu_nonzero) {
    gl.BindBuffer(GL_ARRAY_BUFFER, c.flow_vbo);
    gl.BufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(c.flow.size() * sizeof(float)), c.flow.data());
  }
  c.flow_on_gpu_nonzero = any;
}

void release(const GlApi& gl, GpuMesh& g) {
  if (!g.vao) return;
  gl.DeleteVertexArrays(1, &g.vao);
  gl.DeleteBuffers(1, &g.vbo);
  gl.DeleteBuffers(1, &g.ibo);
}

void draw(const GlApi& gl, const GpuMesh& g) {
  gl.BindVertexArray(g.vao);
  gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(g.indices), GL_UNSIGNED_INT, nullptr);
}

Eigen::Matrix4f model_of(const Eigen::Matrix4d& pose) { return pose.cast<float>(); }

}  // namespace

Renderer::Renderer(OffscreenContext& context, int shadow_map_size)
    : context_(context), shadow_size_(shadow_map_size), gpu_(std::make_unique<Gpu>()) {
  context_.make_current();
  const GlApi& gl = context_.gl();
  gpu_->program = link_program(gl, kVertexShader, kFragmentShader);
  gpu_->depth_program = link_program(gl, kDepthVertexShader, kDepthFragmentShader);
  gl.GenTextures(1, &gpu_->shadow_texture);
  gl.BindTexture(GL_TEXTURE_2D, gpu_->shadow_texture);
  gl.TexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, shadow_size_, shadow_size_, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                nullptr);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl.GenFramebuffers(1, &gpu_->shadow_fbo);
  gl.BindFramebuffer(GL_FRAMEBUFFER, gpu_->shadow_fbo);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, gpu_->shadow_texture, 0);
  gl.DrawBuffer(GL_NONE);
  gl.ReadBuffer(GL_NONE);
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("render: the shadow map's framebuffer is incomplete");
  gpu_->particles = std::make_unique<ParticlesPass>(gl);
  context_.make_current();  // back to the frame's framebuffer
  check_gl(gl, "setting up the renderer");
}

Renderer::~Renderer() {
  context_.make_current();
  const GlApi& gl = context_.gl();
  gpu_->particles.reset();
  for (GpuMesh& g : gpu_->meshes) release(gl, g);
  for (FieldCache& c : gpu_->fields) {
    release(gl, c.gpu);
    if (c.flow_vbo) gl.DeleteBuffers(1, &c.flow_vbo);
  }
  gl.DeleteFramebuffers(1, &gpu_->shadow_fbo);
  gl.DeleteTextures(1, &gpu_->shadow_texture);
  gl.DeleteProgram(gpu_->program);
  gl.DeleteProgram(gpu_->depth_program);
}

void Renderer::render(const Scene& scene, const Camera& camera) {
  context_.make_current();
  const GlApi& gl = context_.gl();
  Gpu& g = *gpu_;
  // Upload what is new or has changed size.
  if (g.meshes.size() < scene.meshes.size()) g.meshes.resize(scene.meshes.size());
  for (std::size_t k = 0; k < scene.meshes.size(); ++k)
    if (g.meshes[k].vertices != scene.meshes[k].positions_m.size() || g.meshes[k].indices != scene.meshes[k].indices.size())
      upload(gl, scene.meshes[k], g.meshes[k], g.interleaved);
  if (g.fields.size() < scene.fields.size()) g.fields.resize(scene.fields.size());
  for (std::size_t k = 0; k < scene.fields.size(); ++k) {
    update_field(gl, scene.fields[k], g.fields[k], g.interleaved);
    advance_flow(gl, scene.fields[k], g.fields[k], scene.time_s);
  }
  const auto draw_all = [&](GLint model_location, GLint colour_location, GLint grain_location) {
    for (const MeshInstance& m : scene.instances) {
      if (m.mesh < 0 || static_cast<std::size_t>(m.mesh) >= scene.meshes.size()) continue;
      gl.UniformMatrix4fv(model_location, 1, GL_FALSE, model_of(m.pose.matrix()).data());
      if (colour_location >= 0) gl.Uniform3fv(colour_location, 1, m.colour.data());
      if (grain_location >= 0) gl.Uniform1f(grain_location, 0.0f);
      draw(gl, g.meshes[static_cast<std::size_t>(m.mesh)]);
    }
    for (std::size_t k = 0; k < scene.fields.size(); ++k) {
      const HeightField& f = scene.fields[k];
      gl.UniformMatrix4fv(model_location, 1, GL_FALSE, model_of(f.pose.matrix()).data());
      if (colour_location >= 0) gl.Uniform3fv(colour_location, 1, f.colour.data());
      if (grain_location >= 0) gl.Uniform1f(grain_location, 1.0f);
      draw(gl, g.fields[k].gpu);
    }
  };
  const Eigen::Matrix4f sun = sun_view_projection(scene);
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LESS);
  gl.Disable(GL_CULL_FACE);  // height fields and open meshes are seen from both sides
  // 1. The sun's depth map.
  gl.BindFramebuffer(GL_FRAMEBUFFER, g.shadow_fbo);
  gl.Viewport(0, 0, shadow_size_, shadow_size_);
  gl.Clear(GL_DEPTH_BUFFER_BIT);
  gl.UseProgram(g.depth_program);
  gl.UniformMatrix4fv(gl.GetUniformLocation(g.depth_program, "sun_view_projection"), 1, GL_FALSE, sun.data());
  draw_all(gl.GetUniformLocation(g.depth_program, "model"), -1, -1);
  // 2. The frame.
  context_.make_current();
  gl.Viewport(0, 0, context_.width(), context_.height());
  gl.ClearColor(scene.sky.x(), scene.sky.y(), scene.sky.z(), 1.0f);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl.UseProgram(g.program);
  const Eigen::Matrix4f view_projection =
      perspective(camera.fov_y_deg, static_cast<double>(context_.width()) / context_.height(), camera.near_m,
                  camera.far_m) *
      look_at(camera.eye_m, camera.target_m, camera.up);
  gl.UniformMatrix4fv(gl.GetUniformLocation(g.program, "view_projection"), 1, GL_FALSE, view_projection.data());
  gl.UniformMatrix4fv(gl.GetUniformLocation(g.program, "sun_view_projection"), 1, GL_FALSE, sun.data());
  const double texel_m = scene.shadow_bounds_m.sizes().head<2>().maxCoeff() / shadow_size_;
  gl.Uniform1f(gl.GetUniformLocation(g.program, "shadow_offset_m"), static_cast<float>(1.5 * texel_m));
  const Eigen::Vector3f to_sun = (-scene.sun_direction.normalized()).cast<float>();
  gl.Uniform3fv(gl.GetUniformLocation(g.program, "to_sun"), 1, to_sun.data());
  gl.Uniform3fv(gl.GetUniformLocation(g.program, "sky"), 1, scene.sky.data());
  const Eigen::Vector3f eye = camera.eye_m.cast<float>();
  gl.Uniform3fv(gl.GetUniformLocation(g.program, "eye"), 1, eye.data());
  gl.Uniform1f(gl.GetUniformLocation(g.program, "flow_time_s"), static_cast<float>(std::fmod(scene.time_s, kFlowPeriodS)));
  gl.Uniform1f(gl.GetUniformLocation(g.program, "flow_phase_s"), static_cast<float>(kFlowPhaseS));
  gl.Uniform1f(gl.GetUniformLocation(g.program, "flow_period_s"), static_cast<float>(kFlowPeriodS));
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindTexture(GL_TEXTURE_2D, g.shadow_texture);
  gl.Uniform1i(gl.GetUniformLocation(g.program, "sun_depth"), 0);
  draw_all(gl.GetUniformLocation(g.program, "model"), gl.GetUniformLocation(g.program, "colour"),
           gl.GetUniformLocation(g.program, "grain"));
  // 3. Dust and falling sand, over it all.
  g.particles->draw(scene.particles, camera, view_projection, scene.sky, to_sun);
  gl.Finish();
  check_gl(gl, "rendering a frame");
}

std::vector<std::uint8_t> render_rgb(OffscreenContext& context, Renderer& renderer, const Scene& scene,
                                     const Camera& camera) {
  renderer.render(scene, camera);
  std::vector<std::uint8_t> rgb;
  context.read_rgb(rgb);
  return rgb;
}

}  // namespace skidsim::render
