// What only the Vulkan backend has, on the machine's device (lavapipe in CI) with the validation layer on:
// timestamps within wall time, agreement with GL, device selection, multiview judged by its images alone, and
// the validation layer's capture. Everything that must hold on every API is in backend_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <memory>

#include "backends/backend.h"
#include "backends/reference/ray_caster.h"
#include "backends/vulkan/vk_context.h"
#include "bench/run/case_runner.h"
#include "bench/truth/accuracy.h"
#include "tests/backend_availability.h"
#include "tests/optimization_checks.h"

namespace omnishadow {
namespace {

const std::string kScenes = OMNISHADOW_TEST_SCENES_DIR;

class VkBackendTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    try {
      backend_ = create_backend("vulkan", {{"api_checks", "1"}});
    } catch (const std::exception& e) {
      skip_reason_ =
          std::string("no Vulkan 1.2 device with the validation layer on this machine: ") + e.what();
      return;
    }
    room_ = std::make_unique<scene::Scene>(scene::load_scene_file(kScenes + "/room.json"));
    backend_->load(*room_);
  }
  static void TearDownTestSuite() { backend_.reset(); }
  void SetUp() override {
    if (!backend_) OMNISHADOW_SKIP_UNAVAILABLE("vulkan", skip_reason_);
  }
  void TearDown() override {
    if (!backend_) return;
    std::vector<std::string> messages = backend_->drain_api_errors();
    EXPECT_TRUE(messages.empty()) << messages.size() << " validation message(s), first: " << messages.front();
  }

  static CaseConfig room_case(Technique t, Filter f = Filter::hard, int cube = 512,
                              Storage s = Storage::linear_depth) {
    return testing::room_case("vulkan", t, f, cube, s);
  }
  static Images render(const CaseConfig& c, int frame = 0) {
    backend_->configure(c);
    backend_->render(frame, FrameKind::check);
    return backend_->read_back();
  }

  static std::unique_ptr<Backend> backend_;
  static std::unique_ptr<scene::Scene> room_;
  static std::string skip_reason_;
};
std::unique_ptr<Backend> VkBackendTest::backend_;
std::unique_ptr<scene::Scene> VkBackendTest::room_;
std::string VkBackendTest::skip_reason_;

TEST_F(VkBackendTest, DeviceIsDescribed) {
  const DeviceInfo& d = backend_->device();
  EXPECT_EQ(d.api.rfind("Vulkan 1.", 0), 0u) << d.api;
  EXPECT_NE(d.renderer, "");
  EXPECT_GE(d.max_cube_size, 4096);
  EXPECT_EQ(d.extra.at("api_checks"), "VK_LAYER_KHRONOS_validation");
  // The build's SPIR-V level, since the driver's compiler sees another program at each.
  EXPECT_EQ(d.extra.at("spirv_optimization").rfind(OMNISHADOW_TEST_SPIRV_OPTIMIZATION " (glslc -O", 0), 0u)
      << d.extra.at("spirv_optimization");
}

TEST_F(VkBackendTest, TimestampsAreWithinWallTime) {
  backend_->configure(room_case(Technique::vs_layer));
  backend_->render(0, FrameKind::check);
  for (int frame = 1; frame < 4; ++frame) {
    FrameTiming t = backend_->render(frame, FrameKind::timed);
    for (const PassTiming* p : {&t.shadow, &t.lighting}) {
      EXPECT_GT(p->gpu_ms, 0.0);
      EXPECT_LE(p->gpu_ms, p->cpu_wall_ms * 1.05 + 0.1);
      EXPECT_LE(p->cpu_submit_ms, p->cpu_wall_ms);
    }
  }
}

TEST_F(VkBackendTest, AgreesWithOpenGl) {
  std::unique_ptr<Backend> gl;
  try {
    gl = create_backend("gl", {});
  } catch (const std::exception& e) {
    OMNISHADOW_SKIP_UNAVAILABLE("gl", std::string("no OpenGL backend to compare with: ") + e.what());
  }
  gl->load(*room_);
  for (Filter f : {Filter::hard, Filter::pcf_grid64}) {
    CaseConfig c = room_case(Technique::six_pass, f, 512);
    Images vk_img = render(c, 60);
    c.backend = "gl";
    gl->configure(c);
    gl->render(60, FrameKind::check);
    Images gl_img = gl->read_back();
    // Not bit-identical: the APIs' clip depth ranges differ, so depth tests and interpolation round apart.
    size_t texels = 0, far_apart = 0;
    float max_diff = 0.0f;
    for (size_t face = 0; face < 6; ++face)
      for (size_t i = 0; i < vk_img.cube_distance[face].size(); ++i) {
        float d = std::fabs(vk_img.cube_distance[face][i] - gl_img.cube_distance[face][i]);
        max_diff = std::max(max_diff, d);
        far_apart += d > 1e-3f;
        ++texels;
      }
    EXPECT_LE(far_apart, texels / 1000)
        << "cube texels more than 1e-3 apart, " << to_string(f) << "; max " << max_diff;
    size_t differing = 0;
    for (size_t i = 0; i < vk_img.shadow_factor.size(); ++i)
      differing += std::fabs(vk_img.shadow_factor[i] - gl_img.shadow_factor[i]) > 0.1f;
    EXPECT_LE(differing, vk_img.shadow_factor.size() / 1000) << to_string(f);
  }
}

TEST_F(VkBackendTest, UnsupportedAndBadRequestsSayWhy) {
  CaseConfig huge = room_case(Technique::six_pass);
  huge.cube_size = backend_->device().max_cube_size + 1;
  Support s = backend_->supports(huge);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.reason.find("maxImageDimensionCube"), std::string::npos) << s.reason;
  EXPECT_FALSE(
      backend_->supports(room_case(Technique::six_pass, Filter::hw_compare2x2, 64, Storage::r32f_distance))
          .ok);
  EXPECT_THROW(backend_->configure(huge), std::runtime_error);
  try {
    create_backend("vulkan", {{"vk_device", "no-such-gpu"}});
    FAIL() << "an unknown device name must not fall back to another device";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("matches no Vulkan device"), std::string::npos) << e.what();
  }
  EXPECT_THROW(create_backend("vulkan", {{"vk_device", "99"}}), std::runtime_error);
}

// Multiview is judged from its images, never from the driver's name: ok exactly when its faces equal
// six_pass's.
TEST_F(VkBackendTest, MultiviewIsJudgedByItsImages) {
  if (!backend_->supports(room_case(Technique::multiview)).ok) GTEST_SKIP() << "multiview unsupported here";
  namespace fs = std::filesystem;
  bench::RunOptions o;
  o.out_dir = (fs::temp_directory_path() / ("omnishadow_mv_" + std::to_string(::getpid()))).string();
  o.scenes_dir = kScenes;
  o.accuracy = false;  // this test is about the technique check; the reference has its own tests
  bench::Harness harness(o);
  harness.add_backend("vulkan", create_backend("vulkan", {{"api_checks", "1"}}));
  bench::CaseResult six, mv;
  six.config = room_case(Technique::six_pass, Filter::hard, 128);
  mv.config = room_case(Technique::multiview, Filter::hard, 128);
  harness.prepare(six);
  harness.prepare(mv);
  ASSERT_EQ(six.status, bench::Status::ok) << six.reason;
  ASSERT_EQ(mv.checks.size(), 4u);  // timed_lit, cube_faces, shadow_factor, lit
  const bench::CheckResult& faces = mv.checks[1];
  EXPECT_EQ(faces.name, "cube_faces");
  EXPECT_EQ(mv.status == bench::Status::ok, faces.difference.differing == 0) << mv.reason;
  if (mv.status == bench::Status::failed_check) {
    std::cout << "multiview on " << backend_->device().renderer << ": " << mv.reason << "\n";
    EXPECT_GT(faces.difference.percent_differing(), 0.0);
    EXPECT_FALSE(faces.diff_image.empty());
  }
  fs::remove_all(o.out_dir);
}

}  // namespace
}  // namespace omnishadow

namespace omnishadow::vk {
namespace {

// The checking mode must see what the validation layer says: an invalid call is captured, once.
TEST(VkValidation, MessagesAreCaptured) {
  std::unique_ptr<VkContext> ctx;
  try {
    ctx = std::make_unique<VkContext>("", true);
  } catch (const std::exception& e) {
    OMNISHADOW_SKIP_UNAVAILABLE("vulkan",
                                std::string("no Vulkan device with the validation layer: ") + e.what());
  }
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = 0;  // invalid: VUID-VkBufferCreateInfo-size-00912
  info.usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  vkCreateBuffer(ctx->device(), &info, nullptr, &buffer);
  if (buffer) vkDestroyBuffer(ctx->device(), buffer, nullptr);
  std::vector<std::string> messages = ctx->drain_messages();
  ASSERT_FALSE(messages.empty());
  EXPECT_NE(messages.front().find("00912"), std::string::npos) << messages.front();
  EXPECT_TRUE(ctx->drain_messages().empty());
}

}  // namespace
}  // namespace omnishadow::vk
