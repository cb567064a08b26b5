#include "core/render/gl/gl_context.h"

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "core/util/error.h"

namespace mtg::render {
namespace {

struct Attempt {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  std::string error;  // empty on success
};

std::string egl_error(const char* step) {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(eglGetError()));
  return std::string(step) + " failed (EGL error " + code + ")";
}

Attempt try_display(EGLDisplay display) {
  Attempt a;
  if (display == EGL_NO_DISPLAY) {
    a.error = "no display";
    return a;
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    a.error = egl_error("eglInitialize");
    return a;
  }
  // EGL_SURFACE_TYPE must be set: the default (window) matches no config on these platforms.
  const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                   EGL_RED_SIZE,     8,               EGL_GREEN_SIZE,      8,
                                   EGL_BLUE_SIZE,    8,               EGL_NONE};
  EGLConfig config = nullptr;
  EGLint n = 0;
  if (!eglChooseConfig(display, config_attribs, &config, 1, &n) || n < 1) {
    a.error = egl_error("eglChooseConfig");
    eglTerminate(display);
    return a;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    a.error = egl_error("eglBindAPI(OpenGL)");
    eglTerminate(display);
    return a;
  }
  const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                    EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
  if (context == EGL_NO_CONTEXT) {
    a.error = egl_error("eglCreateContext(OpenGL 3.3 core)");
    eglTerminate(display);
    return a;
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {  // EGL_KHR_surfaceless_context
    a.error = egl_error("eglMakeCurrent");
    eglDestroyContext(display, context);
    eglTerminate(display);
    return a;
  }
  a.display = display;
  a.context = context;
  return a;
}

struct Devices {
  std::vector<EGLDeviceEXT> hardware, software;
};

Devices egl_devices() {
  auto query = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto query_string =
      reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (query == nullptr) return {};
  EGLDeviceEXT devices[16];
  EGLint n = 0;
  if (!query(16, devices, &n)) return {};
  Devices out;
  for (EGLint i = 0; i < n; ++i) {
    const char* ext = query_string != nullptr ? query_string(devices[i], EGL_EXTENSIONS) : nullptr;
    const bool is_software = ext != nullptr && std::strstr(ext, "EGL_MESA_device_software") != nullptr;
    (is_software ? out.software : out.hardware).push_back(devices[i]);
  }
  return out;
}

// Hardware devices first, device `gpu` of them leading (a pool spreads its renderers over the
// GPUs); a software device (llvmpipe) only if nothing else exists.
std::vector<EGLDeviceEXT> devices_by_preference(int gpu) {
  Devices d = egl_devices();
  if (gpu >= 0 && !d.hardware.empty()) {
    std::rotate(d.hardware.begin(), d.hardware.begin() + (gpu % static_cast<int>(d.hardware.size())), d.hardware.end());
  }
  d.hardware.insert(d.hardware.end(), d.software.begin(), d.software.end());
  return d.hardware;
}

}  // namespace

int hardware_gl_devices() { return static_cast<int>(egl_devices().hardware.size()); }

GlContext::GlContext(int gpu) {
  auto get_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_display == nullptr) throw Error("render: EGL lacks eglGetPlatformDisplayEXT (install libegl1-mesa)");
  std::string tried;
  Attempt found;
  std::string platform;
  for (EGLDeviceEXT device : devices_by_preference(gpu)) {
    found = try_display(get_display(EGL_PLATFORM_DEVICE_EXT, device, nullptr));
    if (found.error.empty()) {
      platform = "EGL device";
      break;
    }
    tried += " device: " + found.error + ";";
  }
  if (platform.empty()) {
    found = try_display(get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr));
    if (!found.error.empty()) {
      throw Error("render: no headless OpenGL 3.3 context:" + tried + " surfaceless: " + found.error);
    }
    platform = "EGL surfaceless";
  }
  display_ = found.display;
  context_ = found.context;
  const auto text = [](GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return std::string(s != nullptr ? s : "?");
  };
  description_ = text(GL_RENDERER) + ", OpenGL " + text(GL_VERSION) + ", " + platform;
}

GlContext::~GlContext() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  eglTerminate(display_);
}

}  // namespace mtg::render
