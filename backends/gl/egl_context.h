#pragma once
// A headless OpenGL 4.5 core context through EGL, with no window system and no surface.
// Platforms: "surfaceless" (EGL_MESA_platform_surfaceless; Mesa's llvmpipe and any Mesa GPU driver) and
// "device" (EGL_EXT_platform_device; picks a GPU by index, as on NVIDIA's proprietary driver).

#include <epoxy/egl.h>

#include <string>

namespace omnishadow::gl {

// The harness renders in a core profile; the compatibility profile exists for tools that ask whether a
// driver's behaviour depends on it (tests/gl_nv_link_probe.cpp).
enum class GlProfile { core, compatibility };

class EglContext {
 public:
  // Throws std::runtime_error naming the EGL call that failed and the EGL error code.
  // `debug` asks for a debug context (KHR_debug messages for the checking mode).
  EglContext(const std::string& platform, int device_index, bool debug, GlProfile profile = GlProfile::core);
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  const std::string& platform() const { return platform_; }
  std::string egl_version() const;
  // Makes this context current on the calling thread again; false when EGL refuses. Needed before any GL call
  // that may follow another API's teardown: on NVIDIA the Vulkan ICD (libGLX_nvidia) shares driver state with
  // EGL, and after vkDestroyInstance libepoxy found no current context for the GL backend's destructor and
  // aborted the process.
  bool make_current() const;

 private:
  void create_context(bool debug, GlProfile profile);  // on the initialised display_, made current
  std::string platform_;
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace omnishadow::gl
