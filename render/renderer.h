// Draws a Scene from a Camera into an OffscreenContext: the sun's shadow map
// first (a depth pass over the scene's shadow bounds), then the colour pass
// (diffuse sun with its shadow, sky light from above, distance haze; sand
// gets a grain pattern fixed to the world). OpenGL 3.3 core.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "render/offscreen_context.h"
#include "render/scene.h"

namespace skidsim::render {

// The sand's moving texture (8.2.3): each of its layers is moved on from
// frame to frame drawn and put back every tau, so a frame depends on the
// frames drawn in the tau before it.
inline constexpr double kFlowPeriodS = 0.9;

class Renderer {
 public:
  explicit Renderer(OffscreenContext& context, int shadow_map_size = 1024);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Renders the frame; read it with context.read_rgb. Meshes are uploaded
  // the first time a Scene's mesh index is seen with that vertex count, and
  // again when it changes. Height fields are kept by index: only the rows
  // whose heights changed since the last frame are remeshed and uploaded.
  void render(const Scene& scene, const Camera& camera);

 private:
  struct Gpu;
  OffscreenContext& context_;
  int shadow_size_;
  std::unique_ptr<Gpu> gpu_;
};

// Renders once and returns the RGB pixels (top row first).
std::vector<std::uint8_t> render_rgb(OffscreenContext& context, Renderer& renderer, const Scene& scene,
                                     const Camera& camera);

}  // namespace skidsim::render
