// nv_swizzle's viewport swizzles (backends/common/viewport_swizzle.h): applied to the vertex stage's
// (p - light, near), each face's swizzle gives the clip x, y and w that six_pass's face matrix gives, bit for
// bit, so both rasterise the same coverage; and its constant clip z clips exactly at the near plane in both
// depth ranges.
#include "backends/common/viewport_swizzle.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace omnishadow::cube {
namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0 || (a == 0.0f && b == 0.0f); }

TEST(ViewportSwizzle, ReproducesEveryFaceMatrixsClipXYWBitForBit) {
  const auto swizzles = face_swizzles();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> near_origin(-20.0f, 20.0f), far_away(-2.0e5f, 2.0e5f);
  for (int i = 0; i < 20000; ++i) {
    // Lights near the origin and far from it (the far-from-origin extremes), points around them.
    const bool far_scene = i % 2 == 1;
    const glm::vec3 light = far_scene ? glm::vec3(far_away(rng), far_away(rng), far_away(rng))
                                      : glm::vec3(near_origin(rng), near_origin(rng), near_origin(rng));
    const glm::vec3 p = light + glm::vec3(near_origin(rng), near_origin(rng), near_origin(rng));
    const float near_plane = 0.1f;
    const glm::vec4 relative(p - light, near_plane);
    for (DepthRange range : {DepthRange::minus_one_to_one, DepthRange::zero_to_one}) {
      const auto matrices = face_view_projections(light, near_plane, 25.0f, range);
      for (int f = 0; f < kFaceCount; ++f) {
        const glm::vec4 expected = matrices[size_t(f)] * glm::vec4(p, 1.0f);
        const glm::vec4 got = apply_swizzle(swizzles[size_t(f)], relative);
        ASSERT_TRUE(same_bits(got.x, expected.x) && same_bits(got.y, expected.y) &&
                    same_bits(got.w, expected.w))
            << "face " << kFaceNames[size_t(f)] << " point " << p.x << "," << p.y << "," << p.z
            << ": swizzled (" << got.x << ", " << got.y << ", " << got.w << ") matrix (" << expected.x << ", "
            << expected.y << ", " << expected.w << ")";
      }
    }
  }
}

TEST(ViewportSwizzle, ClipsAtTheNearPlaneAndStoresDepthFallingWithDistance) {
  const auto swizzles = face_swizzles();
  const float near_plane = 0.5f;
  for (int f = 0; f < kFaceCount; ++f) {
    for (float axis : {0.25f, 0.49f, 0.5f, 0.51f, 1.0f, 100.0f}) {
      const glm::vec3 rel = kFaceDirections[size_t(f)] * axis;
      const glm::vec4 clip = apply_swizzle(swizzles[size_t(f)], glm::vec4(rel, near_plane));
      EXPECT_EQ(clip.w, axis) << "w is the face's axis distance";
      EXPECT_EQ(clip.z, near_plane);
      // Inside both APIs' clip volumes (-w <= z <= w and 0 <= z <= w) exactly when axis >= near.
      EXPECT_EQ(clip.z <= clip.w && clip.z >= -clip.w, axis >= near_plane)
          << kFaceNames[size_t(f)] << " " << axis;
    }
    const glm::vec4 a =
        apply_swizzle(swizzles[size_t(f)], glm::vec4(kFaceDirections[size_t(f)] * 2.0f, near_plane));
    const glm::vec4 b =
        apply_swizzle(swizzles[size_t(f)], glm::vec4(kFaceDirections[size_t(f)] * 3.0f, near_plane));
    EXPECT_GT(a.z / a.w, b.z / b.w) << "reversed: nearer is greater (reversed_depth_test)";
  }
}

TEST(ViewportSwizzle, EachFaceSwizzleIsAPermutationWithItsMajorAxisInW) {
  const auto swizzles = face_swizzles();
  for (int f = 0; f < kFaceCount; ++f) {
    const FaceSwizzle& s = swizzles[size_t(f)];
    EXPECT_EQ(static_cast<uint32_t>(s.w), static_cast<uint32_t>(f))
        << "face f's w is its own axis (+X = pos_x ...)";
    EXPECT_EQ(s.z, SwizzleComponent::pos_w);
    const uint32_t axes =
        (1u << (uint32_t(s.x) / 2)) | (1u << (uint32_t(s.y) / 2)) | (1u << (uint32_t(s.w) / 2));
    EXPECT_EQ(axes, 0b111u) << "x, y and w take the three axes once each";
  }
}

}  // namespace
}  // namespace omnishadow::cube
