// A window-less OpenGL 3.3 core context that renders into a framebuffer
// object of a fixed size: EGL first (the surfaceless platform, which runs on
// a GPU driven by Mesa or on its software rasteriser; then EGL devices, for
// other vendors' GPUs), OSMesa as the fallback. Both render through the same
// framebuffer object, so the rest of the renderer does not know which it has.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/gl_api.h"

namespace skidsim::render {

enum class Backend { kEgl, kOsmesa };
const char* backend_name(Backend backend);

class OffscreenContext {
 public:
  // Throws std::runtime_error saying why the backend could not give a
  // context (no driver, no 3.3 core profile, incomplete framebuffer).
  OffscreenContext(Backend backend, int width, int height);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  // Makes this context current on the calling thread (a recorder thread
  // owns its own context).
  void make_current();
  const GlApi& gl() const { return gl_; }
  Backend backend() const { return backend_; }
  std::string renderer() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  int width() const { return width_; }
  int height() const { return height_; }
  // The framebuffer's pixels as RGB, 8 bits each, top row first.
  void read_rgb(std::vector<std::uint8_t>& rgb) const;

 private:
  struct Native;
  void create_framebuffer();

  Backend backend_;
  int width_, height_;
  std::unique_ptr<Native> native_;
  GlApi gl_;
  GLuint framebuffer_ = 0, colour_ = 0, depth_ = 0;
  mutable std::vector<std::uint8_t> rgba_;
};

// "egl", "osmesa", or "auto" (EGL, else OSMesa). Throws std::runtime_error
// naming both failures when neither works, std::invalid_argument for an
// unknown name.
std::unique_ptr<OffscreenContext> make_offscreen_context(const std::string& backend, int width, int height);

}  // namespace skidsim::render
