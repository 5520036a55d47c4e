// The OpenGL 3.3 core entry points the renderer uses, resolved at run time
// through the current context's loader (eglGetProcAddress or
// OSMesaGetProcAddress). libepoxy resolves through EGL or GLX only, not
// OSMesa, so the renderer keeps this small table of its own.
#pragma once

#include <GL/glcorearb.h>

#include <string>

namespace skidsim::render {

#define SKIDSIM_GL_FUNCTIONS(X)                                                       \
  X(PFNGLGETSTRINGPROC, GetString)                                                    \
  X(PFNGLGETERRORPROC, GetError)                                                      \
  X(PFNGLVIEWPORTPROC, Viewport)                                                      \
  X(PFNGLCLEARCOLORPROC, ClearColor)                                                  \
  X(PFNGLCLEARPROC, Clear)                                                            \
  X(PFNGLENABLEPROC, Enable)                                                          \
  X(PFNGLDISABLEPROC, Disable)                                                        \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                                    \
  X(PFNGLCULLFACEPROC, CullFace)                                                      \
  X(PFNGLPOLYGONOFFSETPROC, PolygonOffset)                                            \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                                  \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                \
  X(PFNGLFINISHPROC, Finish)                                                          \
  X(PFNGLDRAWBUFFERPROC, DrawBuffer)                                                  \
  X(PFNGLREADBUFFERPROC, ReadBuffer)                                                  \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                                        \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                        \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                  \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                          \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                                      \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                                      \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                                \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                                \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)                        \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)                              \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                                \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                                                \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                          \
  X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                                  \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                            \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                            \
  X(PFNGLCREATESHADERPROC, CreateShader)                                              \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                              \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                                            \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                      \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                              \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                            \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                              \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                              \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                    \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                                  \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                            \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                  \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                                      \
  X(PFNGLUNIFORM3FVPROC, Uniform3fv)                                                  \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                                                    \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                                    \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                                        \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                        \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                  \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                                  \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                                  \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                            \
  X(PFNGLBUFFERDATAPROC, BufferData)                                                  \
  X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                                            \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                        \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)                                              \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                                  \
  X(PFNGLBLENDFUNCPROC, BlendFunc)                                                    \
  X(PFNGLDEPTHMASKPROC, DepthMask)                                                    \
  X(PFNGLUNIFORM2FVPROC, Uniform2fv)

struct GlApi {
#define SKIDSIM_GL_MEMBER(type, name) type name = nullptr;
  SKIDSIM_GL_FUNCTIONS(SKIDSIM_GL_MEMBER)
#undef SKIDSIM_GL_MEMBER
};

// Fills `api` from `resolve("glName")`; throws std::runtime_error naming the
// first entry point the context does not have.
using GlResolver = void* (*)(const char* name);
void load_gl_api(GlApi& api, GlResolver resolve);

// A program from a vertex and a fragment shader's source; throws
// std::runtime_error with the compiler's or linker's log.
GLuint link_program(const GlApi& gl, const char* vertex, const char* fragment);

// Throws std::runtime_error naming `what` if GL reports an error.
void check_gl(const GlApi& gl, const std::string& what);

}  // namespace skidsim::render
