#include "render/offscreen_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>

#include <stdexcept>

namespace skidsim::render {

struct OffscreenContext::Native {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext egl = EGL_NO_CONTEXT;
  OSMesaContext osmesa = nullptr;
  std::vector<std::uint8_t> osmesa_buffer;  // OSMesa's own colour buffer (unused: we draw to the FBO)
};

namespace {

void* egl_resolve(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }
void* osmesa_resolve(const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }

std::string egl_error(const char* what) {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", eglGetError());
  return std::string(what) + " (EGL error " + code + ")";
}

// A 3.3 core context on `display`, made current with no surface.
EGLContext egl_context_on(EGLDisplay display, std::string& why) {
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    why = egl_error("eglInitialize failed");
    return EGL_NO_CONTEXT;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    why = egl_error("no desktop OpenGL");
    return EGL_NO_CONTEXT;
  }
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  // No config: the context draws only into framebuffer objects
  // (EGL_KHR_no_config_context, which Mesa and NVIDIA have).
  EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) {
    why = egl_error("no OpenGL 3.3 core context");
    return EGL_NO_CONTEXT;
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    why = egl_error("cannot make the context current without a surface");
    eglDestroyContext(display, context);
    return EGL_NO_CONTEXT;
  }
  return context;
}

}  // namespace

const char* backend_name(Backend backend) { return backend == Backend::kEgl ? "egl" : "osmesa"; }

OffscreenContext::OffscreenContext(Backend backend, int width, int height)
    : backend_(backend), width_(width), height_(height), native_(std::make_unique<Native>()) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw std::invalid_argument("render: a frame of " + std::to_string(width) + " x " + std::to_string(height));
  Native& n = *native_;
  if (backend == Backend::kEgl) {
    std::string why = "EGL has no eglGetPlatformDisplayEXT";
    const auto platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (platform_display) {
      n.display = platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (n.display != EGL_NO_DISPLAY) n.egl = egl_context_on(n.display, why);
      if (n.egl == EGL_NO_CONTEXT) {
        // Another vendor's GPU: its first device that gives a context.
        const auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        EGLDeviceEXT devices[8];
        EGLint count = 0;
        if (query_devices && query_devices(8, devices, &count))
          for (EGLint k = 0; k < count && n.egl == EGL_NO_CONTEXT; ++k) {
            n.display = platform_display(EGL_PLATFORM_DEVICE_EXT, devices[k], nullptr);
            if (n.display != EGL_NO_DISPLAY) n.egl = egl_context_on(n.display, why);
          }
      }
    }
    if (n.egl == EGL_NO_CONTEXT) throw std::runtime_error("render: EGL: " + why);
    load_gl_api(gl_, egl_resolve);
  } else {
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    n.osmesa = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!n.osmesa) throw std::runtime_error("render: OSMesa: no OpenGL 3.3 core context");
    n.osmesa_buffer.resize(4);
    if (!OSMesaMakeCurrent(n.osmesa, n.osmesa_buffer.data(), GL_UNSIGNED_BYTE, 1, 1))
      throw std::runtime_error("render: OSMesa: cannot make the context current");
    load_gl_api(gl_, osmesa_resolve);
  }
  create_framebuffer();
}

OffscreenContext::~OffscreenContext() {
  Native& n = *native_;
  if (framebuffer_) {
    make_current();
    gl_.DeleteFramebuffers(1, &framebuffer_);
    gl_.DeleteRenderbuffers(1, &colour_);
    gl_.DeleteRenderbuffers(1, &depth_);
  }
  if (n.egl != EGL_NO_CONTEXT) {
    eglMakeCurrent(n.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(n.display, n.egl);
  }
  if (n.osmesa) OSMesaDestroyContext(n.osmesa);
}

void OffscreenContext::make_current() {
  Native& n = *native_;
  const bool ok = n.egl != EGL_NO_CONTEXT
                      ? eglMakeCurrent(n.display, EGL_NO_SURFACE, EGL_NO_SURFACE, n.egl) == EGL_TRUE
                      : OSMesaMakeCurrent(n.osmesa, n.osmesa_buffer.data(), GL_UNSIGNED_BYTE, 1, 1) == GL_TRUE;
  if (!ok) throw std::runtime_error(std::string("render: cannot make the ") + backend_name(backend_) + " context current");
  if (framebuffer_) gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
}

void OffscreenContext::create_framebuffer() {
  gl_.GenFramebuffers(1, &framebuffer_);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  gl_.GenRenderbuffers(1, &colour_);
  gl_.BindRenderbuffer(GL_RENDERBUFFER, colour_);
  gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width_, height_);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
  gl_.GenRenderbuffers(1, &depth_);
  gl_.BindRenderbuffer(GL_RENDERBUFFER, depth_);
  gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width_, height_);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  if (gl_.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("render: the " + std::to_string(width_) + " x " + std::to_string(height_) +
                             " framebuffer is incomplete");
  gl_.Viewport(0, 0, width_, height_);
  check_gl(gl_, "creating the framebuffer");
}

std::string OffscreenContext::renderer() const {
  const GLubyte* s = gl_.GetString(GL_RENDERER);
  return s ? reinterpret_cast<const char*>(s) : "";
}

void OffscreenContext::read_rgb(std::vector<std::uint8_t>& rgb) const {
  const auto w = static_cast<std::size_t>(width_), h = static_cast<std::size_t>(height_);
  rgba_.resize(w * h * 4);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  gl_.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl_.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rgba_.data());
  check_gl(gl_, "reading the frame");
  rgb.resize(w * h * 3);
  // GL's rows run bottom to top; images top to bottom.
  for (std::size_t r = 0; r < h; ++r) {
    const std::uint8_t* src = &rgba_[(h - 1 - r) * w * 4];
    std::uint8_t* dst = &rgb[r * w * 3];
    for (std::size_t c = 0; c < w; ++c) {
      dst[3 * c] = src[4 * c];
      dst[3 * c + 1] = src[4 * c + 1];
      dst[3 * c + 2] = src[4 * c + 2];
    }
  }
}

std::unique_ptr<OffscreenContext> make_offscreen_context(const std::string& backend, int width, int height) {
  if (backend == "egl") return std::make_unique<OffscreenContext>(Backend::kEgl, width, height);
  if (backend == "osmesa") return std::make_unique<OffscreenContext>(Backend::kOsmesa, width, height);
  if (backend != "auto") throw std::invalid_argument("render backend '" + backend + "': expected auto, egl or osmesa");
  try {
    return std::make_unique<OffscreenContext>(Backend::kEgl, width, height);
  } catch (const std::runtime_error& egl) {
    try {
      return std::make_unique<OffscreenContext>(Backend::kOsmesa, width, height);
    } catch (const std::runtime_error& osmesa) {
      throw std::runtime_error(std::string(egl.what()) + "; " + osmesa.what());
    }
  }
}

}  // namespace skidsim::render
