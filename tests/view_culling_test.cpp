// Culling to the view: exact answers where the geometry makes them plain (a light behind the camera, a camera
// inside a light's range), and, over random cameras, lights, ranges and reaches, never a face left out that a
// lookup of a visible point in range may read.

#include "backends/common/view_culling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "backends/common/cube_faces.h"
#include "backends/common/shadow_plan.h"

namespace omnishadow {
namespace {

constexpr uint8_t kPlusZ = 1u << 4;  // face order +X, -X, +Y, -Y, +Z, -Z

// A camera at the origin looking along +z, 90 degrees wide and 60 high, near 0.1, far 100.
cube::ViewVolume along_z() {
  scene::Camera camera;
  camera.position = glm::vec3(0.0f);
  camera.target = glm::vec3(0.0f, 0.0f, 1.0f);
  camera.fov_y_degrees = 60.0f;
  camera.near_plane = 0.1f;
  camera.far_plane = 100.0f;
  const float aspect = 1.0f / std::tan(glm::radians(30.0f));  // tan(half x) = 1
  return cube::camera_view(camera, int(std::lround(aspect * 1000.0f)), 1000);
}

TEST(ViewCulling, ALightWhoseRangeMissesTheViewGetsNoMap) {
  const cube::ViewVolume v = along_z();
  const cube::LookupReach hard{0.0f, 2.0f, true};
  EXPECT_EQ(cube::view_face_mask(v, {0, 0, -5}, 3.0f, hard, 64, true), 0) << "behind the camera";
  EXPECT_EQ(cube::view_face_mask(v, {0, 0, 150}, 20.0f, hard, 64, true), 0) << "beyond the far plane";
  EXPECT_EQ(cube::view_face_mask(v, {30, 0, 10}, 10.0f, hard, 64, true), 0) << "beside the frustum";
  EXPECT_NE(cube::view_face_mask(v, {0, 0, -5}, 5.2f, hard, 64, true), 0) << "reaching past the near plane";
  EXPECT_EQ(cube::view_face_mask(v, {0, 0, -5}, 5.2f, hard, 64, false), cube::kAllFaces)
      << "whole lights only where layers are no cube faces";
}

TEST(ViewCulling, OnlyTheFacesTheViewLooksThroughAreKept) {
  const cube::ViewVolume v = along_z();
  const cube::LookupReach hard{0.0f, 2.0f, true};
  // Behind the camera: every visible point in range lies within 42 degrees of +z from the light (x <= z, and
  // z < 9 within range 10: x / (z + 1) < 0.9), inside the +z face and its 2-texel margin (1.0625).
  EXPECT_EQ(cube::view_face_mask(v, {0, 0, -1}, 10.0f, hard, 64, true), kPlusZ);
  // With range 20, x / (z + 1) reaches 0.95: within the margin of the side faces, which are kept.
  EXPECT_EQ(cube::view_face_mask(v, {0, 0, -1}, 20.0f, hard, 64, true), kPlusZ | 0x03);
  // A camera inside the light's range, at the light: the view's half angles (45 and 30 degrees) stay within
  // the +z face, but the widened edges of a 2-texel reach touch the side faces.
  const uint8_t at_light = cube::view_face_mask(v, {0, 0, 0}, 10.0f, hard, 64, true);
  EXPECT_TRUE(at_light & kPlusZ);
  EXPECT_FALSE(at_light & (1u << 5)) << "-z faces away from the view";
  // A wide kernel reaches round the corner: the side faces are kept.
  const cube::LookupReach wide{2.0f, 2.0f, true};
  EXPECT_EQ(cube::view_face_mask(v, {0, 0, -1}, 20.0f, wide, 64, true) & 0x0f, 0x0f);
  // PCSS's reach has no bound: every face of a light in view.
  const cube::LookupReach unbounded{0.0f, 2.0f, false};
  EXPECT_EQ(cube::view_face_mask(v, {0, 0, -1}, 20.0f, unbounded, 64, true), cube::kAllFaces);
}

TEST(ViewCulling, NoFaceALookupOfAVisiblePointReadsIsLeftOut) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), zero_one(0.0f, 1.0f);
  int checked = 0, culled_faces = 0;
  for (int trial = 0; trial < 300; ++trial) {
    scene::Camera camera;
    camera.position = 10.0f * glm::vec3(unit(rng), unit(rng), unit(rng));
    camera.target = camera.position + glm::vec3(unit(rng), unit(rng), unit(rng));
    camera.fov_y_degrees = 20.0f + 80.0f * zero_one(rng);
    camera.far_plane = 5.0f + 40.0f * zero_one(rng);
    const int width = 100 + int(200 * zero_one(rng)), height = 100 + int(200 * zero_one(rng));
    const cube::ViewVolume v = cube::camera_view(camera, width, height);
    const glm::vec3 light = camera.position + 12.0f * glm::vec3(unit(rng), unit(rng), unit(rng));
    const float range = 1.0f + 10.0f * zero_one(rng);
    const cube::LookupReach reach{0.5f * zero_one(rng), 2.0f, true};
    const int face_size = 16;
    const uint8_t mask = cube::view_face_mask(v, light, range, reach, face_size, true);
    culled_faces += 6 - std::popcount(mask);
    // Points in the frustum within range of the light, each looked up through offsets within the reach.
    for (int i = 0; i < 4000; ++i) {
      const float z = v.near_plane + (v.far_plane - v.near_plane) * zero_one(rng);
      const glm::vec3 p = v.eye + z * v.forward + unit(rng) * z * v.tan_half_x * v.right +
                          unit(rng) * z * v.tan_half_y * v.up;
      if (glm::length(p - light) >= range) continue;
      glm::vec3 offset(unit(rng), unit(rng), unit(rng));
      if (glm::length(offset) > 1.0f) continue;
      const uint8_t read = cube::faces_within(p + reach.world * offset - light, reach.texels, face_size);
      ++checked;
      ASSERT_EQ(read & ~mask, 0) << "trial " << trial << ": a visible point reads faces " << int(read)
                                 << ", kept " << int(mask);
    }
  }
  EXPECT_GT(checked, 10000);
  EXPECT_GT(culled_faces, 300) << "the test must see faces culled to mean anything";
}

TEST(ViewCulling, ReachFollowsTheFilter) {
  CaseConfig c;
  c.filter = Filter::hard;
  EXPECT_EQ(gpu::lookup_reach(c, 10.0f, 5.0f, 64).world, 0.0f);
  c.filter = Filter::pcf_disk20;
  const float near_camera = gpu::lookup_reach(c, 10.0f, 5.0f, 64).world;
  EXPECT_GT(gpu::lookup_reach(c, 10.0f, 50.0f, 64).world, near_camera)
      << "the disk widens with view distance";
  c.pcf_scale = 2.0f;
  EXPECT_FLOAT_EQ(gpu::lookup_reach(c, 10.0f, 5.0f, 64).world, 2.0f * near_camera);
  c.filter = Filter::pcss;
  EXPECT_FALSE(gpu::lookup_reach(c, 10.0f, 5.0f, 64).bounded);
  c.filter = Filter::vsm;
  EXPECT_GT(gpu::lookup_reach(c, 10.0f, 5.0f, 64).texels,
            gpu::lookup_reach(CaseConfig{}, 10.0f, 5.0f, 64).texels)
      << "the moments blur carries texels across seams";
  c.filter = Filter::hard;
  c.remedies.normal_offset = true;
  EXPECT_GT(gpu::lookup_reach(c, 10.0f, 5.0f, 64).world, 0.0f) << "the normal offset moves the lookup";
}

TEST(ViewCulling, PlanKeepsOnlyTheGivenFaces) {
  cube::ShadowDrawPlan plan;
  plan.object_faces = {cube::kAllFaces, 0x01, 0x30};
  for (uint32_t i = 0; i < 3; ++i)
    for (int f = 0; f < 6; ++f)
      if (plan.object_faces[i] >> f & 1) plan.face_objects[size_t(f)].push_back(i);
  cube::keep_faces(plan, 0x11);  // +X and +Z
  EXPECT_EQ(plan.object_faces, (std::vector<uint8_t>{0x11, 0x01, 0x10}));
  EXPECT_EQ(plan.reaching, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(plan.empty_faces, 4);
  EXPECT_EQ(plan.face_objects[4], (std::vector<uint32_t>{0, 2}));
  cube::keep_faces(plan, 0);
  EXPECT_TRUE(plan.reaching.empty());
  EXPECT_EQ(plan.empty_faces, 6);
}

}  // namespace
}  // namespace omnishadow
