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

// --gl-profile: the context named, said in the device record; a compatibility context renders the core one's
// images bit for bit (the shaders are `#version 450`, core GLSL in either context: only the context differs),
// so nv_swizzle may run in one where only that links its passthrough stage (NVIDIA: gl_passthrough.h) and
// stay comparable with the other techniques.
TEST(GlProfiles, ACompatibilityContextRendersTheCoreContextsImages) {
  std::map<std::string, Images> images;
  for (const std::string profile : {"core", "compatibility"}) {
    std::string why;
    auto backend = gl_or_skip_reason({{"gl_profile", profile}}, why);
    if (!backend) OMNISHADOW_SKIP_UNAVAILABLE("gl", why);
    EXPECT_NE(backend->device().api.find(" " + profile), std::string::npos) << backend->device().api;
    EXPECT_EQ(backend->device().extra.at("gl_profile").rfind(profile + " (--gl-profile)", 0), 0u);
    backend->load(scene::load_scene_file(kScenes + "/room.json"));
    CaseConfig c;
    c.backend = "gl";
    c.scene = "room";
    c.technique = Technique::geometry_shader;
    c.filter = Filter::pcf_disk20;
    c.cube_size = 64;
    backend->configure(c);
    backend->render(0, FrameKind::check);
    images[profile] = backend->read_back();
  }
  for (size_t f = 0; f < 6; ++f)
    EXPECT_EQ(images["core"].cube_distance[f], images["compatibility"].cube_distance[f]);
  EXPECT_EQ(images["core"].lit_rgba8, images["compatibility"].lit_rgba8);
  EXPECT_FALSE(images["core"].lit_rgba8.empty());
  EXPECT_THROW(create_backend("gl", {{"gl_profile", "es"}}), std::runtime_error);
}

// Each backend owns an EGL context, and GL calls go to the thread's current one: a backend brought up while
// another lives (it makes its own current) or torn down (it leaves none current) must not leave the first one
// rendering into the wrong context or into none (libepoxy aborts the process then). Each backend makes its
// own context current at every entry: the first one's images are the same before, beside and after the other.
TEST(GlContexts, ABackendRendersTheSameBesideAndAfterAnother) {
  std::string why;
  auto first = gl_or_skip_reason({}, why);
  if (!first) OMNISHADOW_SKIP_UNAVAILABLE("gl", why);
  const scene::Scene room = scene::load_scene_file(kScenes + "/room.json");
  CaseConfig c;
  c.backend = "gl";
  c.scene = "room";
  c.technique = Technique::six_pass;
  c.cube_size = 32;
  auto render = [&](Backend& b) {
    b.configure(c);
    b.render(3, FrameKind::check);
    return b.read_back();
  };
  first->load(room);
  const Images alone = render(*first);
  auto second = gl_or_skip_reason({}, why);
  ASSERT_TRUE(second) << why;
  second->load(room);
  const Images beside = render(*first);
  const Images others = render(*second);
  second.reset();
  const Images after = render(*first);
  EXPECT_FALSE(alone.lit_rgba8.empty());
  for (const Images* img : {&beside, &others, &after}) {
    EXPECT_EQ(img->lit_rgba8, alone.lit_rgba8);
    for (size_t f = 0; f < 6; ++f) EXPECT_EQ(img->cube_distance[f], alone.cube_distance[f]);
  }
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
