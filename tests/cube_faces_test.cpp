// Face order, up vectors and projections: a point in each direction lands in the face and texel that
// cube-map sampling reads for that direction.

#include "backends/common/cube_faces.h"

#include <gtest/gtest.h>

#include <cmath>

namespace omnishadow::cube {
namespace {

// Where `point` lands when face `face` is rendered: window coordinates in [0, size), x = s axis, y = t axis
// (row 0 = first row in memory), and NDC depth.
struct Landing {
  bool inside;
  float x, y, depth;
};
Landing project(int face, glm::vec3 light, glm::vec3 point, int size, DepthRange range) {
  glm::vec4 clip =
      face_view_projections(light, 0.5f, 50.0f, range)[static_cast<size_t>(face)] * glm::vec4(point, 1);
  glm::vec3 ndc = glm::vec3(clip) / clip.w;
  bool inside = clip.w > 0 && std::fabs(ndc.x) <= 1 && std::fabs(ndc.y) <= 1;
  return {inside, (ndc.x + 1) * 0.5f * size, (ndc.y + 1) * 0.5f * size, ndc.z};
}

TEST(CubeFaces, PointOnPlusXLandsInFaceZeroAtTheExpectedTexel) {
  // Direction (5, 1, -2): major axis +X; sc = -rz = 2, tc = -ry = -1 -> s = 0.7, t = 0.4 (spec table 8.19).
  FaceCoord fc = direction_to_face({5, 1, -2});
  EXPECT_EQ(fc.face, 0);
  EXPECT_FLOAT_EQ(fc.s, 0.7f);
  EXPECT_FLOAT_EQ(fc.t, 0.4f);
  Landing l = project(0, {0, 0, 0}, {5, 1, -2}, 512, DepthRange::minus_one_to_one);
  ASSERT_TRUE(l.inside);
  EXPECT_EQ(static_cast<int>(l.x), 358);  // texel column floor(0.7 * 512)
  EXPECT_EQ(static_cast<int>(l.y), 204);  // texel row floor(0.4 * 512)
}

TEST(CubeFaces, EveryDirectionLandsWhereSamplingReadsIt) {
  const glm::vec3 light(1.5f, -2.0f, 0.25f);
  const int size = 1024;
  int checked[6] = {0, 0, 0, 0, 0, 0};
  // A deterministic spread of directions over the sphere (no RNG: a lattice with irrational steps).
  for (int i = 0; i < 4000; ++i) {
    float z = 1.0f - 2.0f * (static_cast<float>(i) + 0.5f) / 4000.0f;
    float phi = 2.39996323f * static_cast<float>(i);
    float r = std::sqrt(1 - z * z);
    glm::vec3 dir(r * std::cos(phi), r * std::sin(phi), z);
    FaceCoord fc = direction_to_face(dir);
    glm::vec3 point = light + 7.0f * dir;
    for (DepthRange range : {DepthRange::minus_one_to_one, DepthRange::zero_to_one}) {
      Landing l = project(fc.face, light, point, size, range);
      ASSERT_TRUE(l.inside) << "face " << fc.face << " does not contain its own direction";
      EXPECT_NEAR(l.x / size, fc.s, 1e-4) << "face " << kFaceNames[fc.face];
      EXPECT_NEAR(l.y / size, fc.t, 1e-4) << "face " << kFaceNames[fc.face];
    }
    ++checked[fc.face];
  }
  for (int f = 0; f < 6; ++f) EXPECT_GT(checked[f], 400) << "face " << kFaceNames[f] << " barely sampled";
}

TEST(CubeFaces, FaceOrderAndUpVectorsAreTheSeeds) {
  EXPECT_EQ(kFaceDirections[0], glm::vec3(1, 0, 0));
  EXPECT_EQ(kFaceDirections[3], glm::vec3(0, -1, 0));
  EXPECT_EQ(kFaceDirections[5], glm::vec3(0, 0, -1));
  EXPECT_EQ(kFaceUps[2], glm::vec3(0, 0, 1));
  EXPECT_EQ(kFaceUps[3], glm::vec3(0, 0, -1));
  for (int f : {0, 1, 4, 5}) EXPECT_EQ(kFaceUps[static_cast<size_t>(f)], glm::vec3(0, -1, 0));
}

TEST(CubeFaces, ProjectionIsNinetyDegreesAndDepthRangesDifferOnlyInDepth) {
  // A point on a face's frustum edge (45 degrees off axis) lands on the NDC border.
  Landing edge = project(4, {0, 0, 0}, {3, 0, 3}, 2, DepthRange::minus_one_to_one);
  EXPECT_NEAR(edge.x, 2.0f, 1e-5);
  Landing gl = project(4, {0, 0, 0}, {0.2f, 0.1f, 0.5f}, 64, DepthRange::minus_one_to_one);
  Landing vk = project(4, {0, 0, 0}, {0.2f, 0.1f, 0.5f}, 64, DepthRange::zero_to_one);
  EXPECT_FLOAT_EQ(gl.x, vk.x);
  EXPECT_FLOAT_EQ(gl.y, vk.y);
  EXPECT_NEAR(gl.depth, -1.0f, 1e-5);  // on the near plane (0.5)
  EXPECT_NEAR(vk.depth, 0.0f, 1e-5);
}

}  // namespace
}  // namespace omnishadow::cube

namespace omnishadow::cube {
namespace {

// texel_direction inverts the sampling table: every texel's direction selects that face and that texel again.
TEST(TexelDirection, RoundTripsThroughTheSamplingTable) {
  const int size = 16;
  for (int f = 0; f < kFaceCount; ++f)
    for (int t = 0; t < size; ++t)
      for (int s = 0; s < size; ++s) {
        FaceCoord c = direction_to_face(texel_direction(f, s, t, size));
        ASSERT_EQ(c.face, f) << s << "," << t;
        EXPECT_EQ(static_cast<int>(c.s * size), s) << "face " << f;
        EXPECT_EQ(static_cast<int>(c.t * size), t) << "face " << f;
      }
}

}  // namespace
}  // namespace omnishadow::cube
