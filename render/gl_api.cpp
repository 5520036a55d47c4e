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

namespace {

GLuint compile(const GlApi& gl, GLenum type, const char* source) {
  const GLuint shader = gl.CreateShader(type);
  gl.ShaderSource(shader, 1, &source, nullptr);
  gl.CompileShader(shader);
  GLint ok = 0;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    gl.GetShaderInfoLog(shader, sizeof log, nullptr, log);
    gl.DeleteShader(shader);
    throw std::runtime_error(std::string("render: shader does not compile: ") + log);
  }
  return shader;
}

}  // namespace

GLuint link_program(const GlApi& gl, const char* vertex, const char* fragment) {
  const GLuint v = compile(gl, GL_VERTEX_SHADER, vertex);
  GLuint f = 0;
  try {
    f = compile(gl, GL_FRAGMENT_SHADER, fragment);
  } catch (...) {
    gl.DeleteShader(v);
    throw;
  }
  const GLuint p = gl.CreateProgram();
  gl.AttachShader(p, v);
  gl.AttachShader(p, f);
  gl.LinkProgram(p);
  gl.DeleteShader(v);
  gl.DeleteShader(f);
  GLint ok = 0;
  gl.GetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    gl.GetProgramInfoLog(p, sizeof log, nullptr, log);
    gl.DeleteProgram(p);
    throw std::runtime_error(std::string("render: shaders do not link: ") + log);
  }
  return p;
}

}  // namespace skidsim::render
