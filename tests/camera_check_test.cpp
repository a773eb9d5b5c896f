// The camera check on images made without a GPU: a wall seen from a camera, each pixel's position where the
// ray through its centre meets the wall. Seen from the check frame's camera it passes, exactly and under a
// perturbation within what the APIs guarantee (positions moved by a sixteenth of a pixel, the subpixel grid);
// seen from another frame's place on a walking camera's path, with the rows in the other order or with
// another aspect, it fails.

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "bench/truth/case_checks.h"

namespace omnishadow::bench {
namespace {

constexpr int kWidth = 64, kHeight = 48;

scene::Scene walking_scene() {
  scene::Scene s;
  s.camera.position = {0.0f, 1.0f, 6.0f};
  s.camera.target = {0.0f, 1.0f, 0.0f};
  s.camera.fov_y_degrees = 50.0f;
  s.camera.path.amplitude = {2.0f, 0.0f, 0.0f};
  s.camera.path.frequency = scene::kSeedLightFrequency;
  return s;
}

// What `camera` sees of the wall z = -2 at width x height, row 0 at clip y = -1; `shift` moves each pixel's
// sample point (in pixels) before the ray is cast.
Images seen_from(const scene::Camera& camera, int width, int height, glm::vec2 shift = {0.0f, 0.0f}) {
  Images img;
  img.width = width;
  img.height = height;
  img.world_position.assign(4 * size_t(width) * size_t(height), 0.0f);
  const glm::mat4 inverse =
      glm::inverse(glm::perspectiveRH_NO(glm::radians(camera.fov_y_degrees), float(width) / float(height),
                                         camera.near_plane, camera.far_plane) *
                   glm::lookAtRH(camera.position, camera.target, camera.up));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const glm::vec2 ndc((float(x) + 0.5f + shift.x) / float(width) * 2.0f - 1.0f,
                          (float(y) + 0.5f + shift.y) / float(height) * 2.0f - 1.0f);
      const glm::vec4 far_point = inverse * glm::vec4(ndc, 1.0f, 1.0f);
      const glm::vec3 direction = glm::normalize(glm::vec3(far_point) / far_point.w - camera.position);
      const float t = (-2.0f - camera.position.z) / direction.z;
      const glm::vec3 p = camera.position + t * direction;
      float* out = &img.world_position[4 * (size_t(y) * size_t(width) + size_t(x))];
      out[0] = p.x, out[1] = p.y, out[2] = p.z, out[3] = 1.0f;
    }
  return img;
}

std::string judged(const scene::Scene& s, const Images& img, int check_frame) {
  static const DeviceInfo device;
  CheckOptions options;
  options.check_frame = check_frame;
  CaseFindings r;
  check_camera(r, img, CheckContext{s, device, options, {}});
  return r.reason;
}

TEST(CameraCheck, TheFrameSeenFromItsCameraPasses) {
  const scene::Scene s = walking_scene();
  for (int frame : {0, 60, 188}) {
    const scene::Camera at = s.camera.at(frame);
    EXPECT_EQ(judged(s, seen_from(at, kWidth, kHeight), frame), "") << "frame " << frame;
    EXPECT_EQ(judged(s, seen_from(at, kWidth, kHeight, {1.0f / 16.0f, -1.0f / 16.0f}), frame), "")
        << "frame " << frame << ", sampled a subpixel step off the centre";
  }
}

TEST(CameraCheck, AFrameSeenFromElsewhereFails) {
  const scene::Scene s = walking_scene();
  const std::string rest = judged(s, seen_from(s.camera, kWidth, kHeight), 188);
  EXPECT_NE(rest.find("frame 188's camera puts elsewhere"), std::string::npos) << rest;
  Images flipped = seen_from(s.camera.at(188), kWidth, kHeight);
  const Images upright = flipped;
  for (int y = 0; y < kHeight; ++y)
    std::copy_n(&upright.world_position[4 * size_t(kHeight - 1 - y) * kWidth], 4 * kWidth,
                &flipped.world_position[4 * size_t(y) * kWidth]);
  EXPECT_NE(judged(s, flipped, 188), "") << "rows in the other order";
  scene::Camera square = s.camera.at(188);
  Images stretched = seen_from(square, kHeight, kHeight);
  stretched.width = kWidth;  // a square frame's positions read as the wide frame's
  stretched.world_position.resize(4 * size_t(kWidth) * kHeight, 0.0f);
  EXPECT_NE(judged(s, stretched, 188), "") << "another aspect";
  EXPECT_NE(judged(s, seen_from(s.camera.at(188), kWidth, kHeight, {0.75f, 0.0f}), 188), "")
      << "three quarters of a pixel off";
}

}  // namespace
}  // namespace omnishadow::bench
