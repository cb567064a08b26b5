#pragma once
// One headless OpenGL 3.3 core context per process (EGL, no window system). The EGL device
// platform comes first, preferring a hardware device (a real GPU), then Mesa's surfaceless
// platform (llvmpipe on the CPU), so the same binary renders on a laptop, in CI and on a GPU box.

#include <string>

namespace mtg::render {

class GlContext {
 public:
  /// Creates the context and makes it current on this thread: on hardware device `gpu` (modulo
  /// how many there are; -1 = the first that works), else on any other device, else surfaceless.
  /// @throws mtg::Error saying which EGL step failed on each platform tried.
  explicit GlContext(int gpu = -1);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  /// e.g. "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6, EGL device".
  const std::string& description() const { return description_; }

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  std::string description_;
};

/// Hardware EGL devices (GPUs) on this machine; 0 where only llvmpipe (or no EGL) is present.
int hardware_gl_devices();

}  // namespace mtg::render
