#include "backends/gl/egl_context.h"

#include <cstdio>
#include <map>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace omnishadow::gl {
namespace {

[[noreturn]] void egl_fail(const char* call) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%s failed (EGL error 0x%04x)", call, static_cast<unsigned>(eglGetError()));
  throw std::runtime_error(buf);
}

bool has_client_extension(const char* name) {
  // Client extensions are queried on EGL_NO_DISPLAY (EGL_EXT_client_extensions).
  return epoxy_has_egl_extension(EGL_NO_DISPLAY, name);
}

EGLDisplay open_display(const std::string& platform, int device_index) {
  // Use the EXT entry point: with libepoxy, eglGetPlatformDisplay (EGL 1.5) is not reliably resolvable here.
  if (platform == "surfaceless") {
    if (!has_client_extension("EGL_MESA_platform_surfaceless"))
      throw std::runtime_error("EGL_MESA_platform_surfaceless is not available (try --egl-platform device)");
    return eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  }
  if (platform == "device") {
    if (!has_client_extension("EGL_EXT_platform_device") ||
        !has_client_extension("EGL_EXT_device_enumeration"))
      throw std::runtime_error("--egl-platform device --gl-device " + std::to_string(device_index) +
                               ": this EGL has no EGL_EXT_platform_device / EGL_EXT_device_enumeration (use "
                               "--egl-platform surfaceless)");
    EGLint count = 0;
    if (!eglQueryDevicesEXT(0, nullptr, &count)) egl_fail("eglQueryDevicesEXT");
    std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
    if (!eglQueryDevicesEXT(count, devices.data(), &count)) egl_fail("eglQueryDevicesEXT");
    if (device_index < 0 || device_index >= count)
      throw std::runtime_error("--gl-device " + std::to_string(device_index) +
                               " is out of range: " + std::to_string(count) + " EGL device(s)");
    return eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[static_cast<size_t>(device_index)],
                                    nullptr);
  }
  throw std::runtime_error("unknown --egl-platform '" + platform + "' (valid: surfaceless, device)");
}

// EGL keeps one initialisation per display, not a count: eglInitialize on an initialised display does
// nothing, and eglTerminate ends every context on it (EGL 1.5, 3.2). Every context of a platform shares its
// display, so a backend torn down while another lives must leave the display initialised: it is terminated
// with its last context.
std::mutex display_mutex;
std::map<EGLDisplay, int> display_users;

void initialize_display(EGLDisplay display) {
  std::lock_guard<std::mutex> lock(display_mutex);
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) egl_fail("eglInitialize");
  ++display_users[display];
}

void release_display(EGLDisplay display) {
  std::lock_guard<std::mutex> lock(display_mutex);
  if (--display_users[display] > 0) return;
  display_users.erase(display);
  eglTerminate(display);
}

}  // namespace

EglContext::EglContext(const std::string& platform, int device_index, bool debug, GlProfile profile)
    : platform_(platform) {
  display_ = open_display(platform, device_index);
  if (display_ == EGL_NO_DISPLAY) egl_fail("eglGetPlatformDisplayEXT");
  initialize_display(display_);
  try {
    create_context(debug, profile);
  } catch (...) {
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    release_display(display_);
    throw;
  }
}

void EglContext::create_context(bool debug, GlProfile profile) {
  if (!eglBindAPI(EGL_OPENGL_API)) egl_fail("eglBindAPI(EGL_OPENGL_API)");
  if (!epoxy_has_egl_extension(display_, "EGL_KHR_surfaceless_context"))
    throw std::runtime_error("EGL_KHR_surfaceless_context is not available on this display");

  // No config and no surface: everything renders into our own framebuffer objects.
  EGLConfig config = nullptr;
  if (!epoxy_has_egl_extension(display_, "EGL_KHR_no_config_context")) {
    const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(display_, config_attribs, &config, 1, &n) || n < 1) egl_fail("eglChooseConfig");
  }
  const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                    4,
                                    EGL_CONTEXT_MINOR_VERSION,
                                    5,
                                    EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                    profile == GlProfile::core ? EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT
                                                               : EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT,
                                    EGL_CONTEXT_OPENGL_DEBUG,
                                    debug ? EGL_TRUE : EGL_FALSE,
                                    EGL_NONE};
  context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, context_attribs);
  if (context_ == EGL_NO_CONTEXT)
    egl_fail(profile == GlProfile::core ? "eglCreateContext(OpenGL 4.5 core)"
                                        : "eglCreateContext(OpenGL 4.5 compatibility)");
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) egl_fail("eglMakeCurrent");
}

EglContext::~EglContext() {
  if (display_ == EGL_NO_DISPLAY) return;
  // Released only where it is current: another backend's context may be the current one.
  if (eglGetCurrentContext() == context_)
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
  release_display(display_);
}

bool EglContext::make_current() const {
  if (display_ == EGL_NO_DISPLAY || context_ == EGL_NO_CONTEXT) return false;
  if (eglGetCurrentContext() == context_) return true;
  return eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) == EGL_TRUE;
}

std::string EglContext::egl_version() const {
  const char* v = eglQueryString(display_, EGL_VERSION);
  return v ? v : "?";
}

}  // namespace omnishadow::gl
