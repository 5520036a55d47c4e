#include "render/gl_api.h"

#include <stdexcept>

namespace skidsim::render {

void load_gl_api(GlApi& api, GlResolver resolve) {
#define SKIDSIM_GL_LOAD(type, name)                                                          \
  api.name = reinterpret_cast<type>(resolve("gl" #name));                                     \
  if (!api.name) throw std::runtime_error("OpenGL: the context has no gl" #name);
  SKIDSIM_GL_FUNCTIONS(SKIDSIM_GL_LOAD)
#undef SKIDSIM_GL_LOAD
}

void check_gl(const GlApi& gl, const std::string& what) {
  const GLenum e = gl.GetError();
  if (e != GL_NO_ERROR) throw std::runtime_error("OpenGL error " + std::to_string(e) + " in " + what);
}

}  // namespace skidsim::render
