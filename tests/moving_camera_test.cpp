// A camera that walks through the scene (Camera::path): it is a function of the frame index, keeps its
// direction, and every per-frame decision that depends on the view (the frame's matrices, the faces culled to
// the view, the clustered lists' frustum) reads it where that frame has it.

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "backends/common/frame_uniforms.h"
#include "backends/common/light_clusters.h"
#include "backends/common/view_culling.h"
#include "scenes/scene.h"

namespace omnishadow {
namespace {

const std::string kScenes = OMNISHADOW_TEST_SCENES_DIR;

// The hall seen from mid-hall looking down it (+x), walked back along it by up to 16 units: at frame 188
// (sin(0.5 * 188 / 60) = 1.0) it stands at x = -16, where the lamps between -16 and 0 are before it.
scene::Scene walking_hall() {
  scene::Scene hall = scene::load_scene_file(kScenes + "/hall.json");
  hall.camera.position = {0.0f, 3.0f, 0.0f};
  hall.camera.target = {20.0f, 2.0f, 0.0f};
  hall.camera.path.amplitude = {-16.0f, 0.0f, 0.0f};
  hall.camera.path.frequency = scene::kSeedLightFrequency;
  return hall;
}
constexpr int kFarFrame = 188;

TEST(MovingCamera, ItIsAFunctionOfTheFrameAndKeepsItsDirection) {
  const scene::Scene hall = walking_hall();
  const scene::Camera& rest = hall.camera;
  EXPECT_TRUE(rest.moves());
  EXPECT_EQ(rest.at(0).position, rest.position) << "phase 0: where the file put it";
  for (int frame : {1, 60, kFarFrame, 1000}) {
    const scene::Camera c = rest.at(frame);
    EXPECT_FALSE(c.moves()) << "the camera of one frame stands still";
    EXPECT_EQ(c.position - rest.position, rest.path.at(frame));
    EXPECT_EQ(c.target - rest.position, rest.target - rest.position + rest.path.at(frame));
    EXPECT_EQ(c.up, rest.up);
    EXPECT_EQ(c.fov_y_degrees, rest.fov_y_degrees);
    EXPECT_EQ(c.at(frame).position, c.position) << "a frame's camera does not move again";
  }
  EXPECT_NEAR(rest.at(kFarFrame).position.x, -16.0f, 1e-3f);
  scene::Camera still = rest;
  still.path = {};
  EXPECT_EQ(still.at(kFarFrame).position, still.position);
}

TEST(MovingCamera, TheFrameUniformsSeeThroughTheCameraOfTheirFrame) {
  const scene::Scene hall = walking_hall();
  CaseConfig c;
  c.width = 96;
  c.height = 64;
  for (int frame : {0, kFarFrame}) {
    const scene::Camera cam = hall.camera.at(frame);
    const gpu::FrameUniforms u = gpu::make_frame_uniforms(hall, frame, c, cube::DepthRange::zero_to_one);
    EXPECT_EQ(glm::vec3(u.camera_position), cam.position) << "frame " << frame;
    const glm::mat4 want =
        glm::perspectiveRH_ZO(glm::radians(cam.fov_y_degrees), 96.0f / 64.0f, cam.near_plane, cam.far_plane) *
        glm::lookAtRH(cam.position, cam.target, cam.up);
    EXPECT_EQ(u.camera_view_proj, want) << "frame " << frame;
  }
}

// The lamp at (-14, 5.5, -4.5) (range 12) is behind the camera at rest, by more than its range: no map. At
// frame 188 the camera stands 2 units behind it, within its range: it lights what the camera sees.
TEST(MovingCamera, ViewCullingCullsToTheViewOfTheFrame) {
  scene::Scene hall = walking_hall();
  int lamp = -1;
  for (size_t k = 0; k < hall.point_lights.size(); ++k)
    if (hall.point_lights[k].path.at(0) == glm::vec3(-14.0f, 5.5f, -4.5f)) lamp = int(k);
  ASSERT_GE(lamp, 0) << "the hall's lamp at x = -14";
  CaseConfig c;
  c.width = 96;
  c.height = 64;
  c.optimizations.view_culling = true;
  scene::FocusLight focus(hall, lamp);
  const float range = hall.light().far_plane;
  EXPECT_EQ(gpu::view_faces(hall, c, 0, range, 32), 0) << "behind the camera at rest";
  EXPECT_NE(gpu::view_faces(hall, c, kFarFrame, range, 32), 0) << "before the camera at frame 188";
}

// The lists built for frame 188 over the grid made at configure (the camera at rest) list the lamp at x = -14
// where the walked camera sees it: the builder takes the frame's camera, not the one it was made with.
TEST(MovingCamera, TheClusteredListsFollowTheCamera) {
  const scene::Scene hall = walking_hall();
  gpu::LightClusterBuilder builder(gpu::cluster_grid(hall.camera, 96, 64));
  gpu::PointLightRecord lamp{};
  lamp.position_far = glm::vec4(-14.0f, 5.5f, -4.5f, 12.0f);
  const std::vector<gpu::PointLightRecord> records{lamp};
  auto listed_anywhere = [](const std::vector<uint32_t>& words, const gpu::ClusterGrid& g) {
    for (int c = 0; c < g.clusters(); ++c)
      if (words[gpu::kClusterHeaderWords + 2 * size_t(c) + 1] > 0) return true;
    return false;
  };
  EXPECT_FALSE(listed_anywhere(builder.build(hall.camera.at(0), records), builder.grid()))
      << "behind the camera at rest";
  const std::vector<uint32_t>& words = builder.build(hall.camera.at(kFarFrame), records);
  EXPECT_TRUE(listed_anywhere(words, builder.grid())) << "before the camera at frame 188";
  EXPECT_EQ(builder.grid().view.eye, hall.camera.at(kFarFrame).position);
}

}  // namespace
}  // namespace omnishadow
