// What only the GL backend has: its version string, KHR_debug capture in the checking mode, and the EGL
// platforms. Everything that must hold on every API is in backend_test.cpp, written once for both.

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <memory>

#include "backends/backend.h"
#include "tests/backend_availability.h"

namespace omnishadow {
namespace {

const std::string kScenes = OMNISHADOW_TEST_SCENES_DIR;

std::unique_ptr<Backend> gl_or_skip_reason(const std::map<std::string, std::string>& options,
                                           std::string& why) {
  try {
    return create_backend("gl", options);
  } catch (const std::exception& e) {
    why = std::string("no OpenGL 4.5 context through EGL on this machine: ") + e.what();
    return nullptr;
  }
}

TEST(GlBackend, DescribesAnOpenGl45CoreContext) {
  std::string why;
  auto backend = gl_or_skip_reason({}, why);
  if (!backend) OMNISHADOW_SKIP_UNAVAILABLE("gl", why);
  const DeviceInfo& d = backend->device();
  EXPECT_EQ(d.api.rfind("OpenGL 4.", 0), 0u) << d.api;
  EXPECT_NE(d.version.find("4."), std::string::npos) << d.version;
  EXPECT_EQ(d.platform.rfind("EGL ", 0), 0u) << d.platform;
}

// The checking mode: a debug context whose KHR_debug errors reach the harness, each once.
TEST(GlApiChecks, ErrorsAreCapturedOnce) {
  std::string why;
  auto backend = gl_or_skip_reason({{"api_checks", "1"}}, why);
  if (!backend) OMNISHADOW_SKIP_UNAVAILABLE("gl", why);
  backend->load(scene::load_scene_file(kScenes + "/ogldev.json"));
  EXPECT_TRUE(backend->drain_api_errors().empty());
  glEnable(0x7fff);  // not a capability: GL_INVALID_ENUM, reported through KHR_debug
  std::vector<std::string> errors = backend->drain_api_errors();
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_TRUE(backend->drain_api_errors().empty()) << "drained once";
}

TEST(GlPlatforms, DevicePlatformOrAClearError) {
  try {
    auto backend = create_backend("gl", {{"egl_platform", "device"}, {"gl_device", "0"}});
    EXPECT_NE(backend->device().platform.find("device"), std::string::npos);
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);  // one line, whatever the reason
  }
  EXPECT_THROW(create_backend("gl", {{"egl_platform", "wayland"}}), std::runtime_error);
  EXPECT_THROW(create_backend("gl", {{"egl_platform", "device"}, {"gl_device", "999"}}), std::runtime_error);
  EXPECT_THROW(create_backend("vulkan-not-yet", {}), std::invalid_argument);
}

}  // namespace
}  // namespace omnishadow
