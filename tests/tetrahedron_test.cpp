// Tetrahedral conventions (backends/common/tetrahedron.h): four orthonormal camera bases along a regular
// tetrahedron, every direction inside the frustum of the face it selects (the layout covers the sphere), the
// face matrices land each texel's direction on that texel in both APIs' depth ranges, and the layers hold a
// cube's memory.
#include "backends/common/tetrahedron.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace omnishadow::tetra {
namespace {

TEST(Tetrahedron, FacesAreOrthonormalCamerasAlongARegularTetrahedron) {
  for (int f = 0; f < kFaceCount; ++f) {
    const Face& a = faces()[size_t(f)];
    for (const glm::dvec3& v : {a.axis, a.right, a.up}) EXPECT_NEAR(glm::length(v), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(a.axis, a.up), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(a.axis, a.right), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(glm::cross(a.right, a.up) + a.axis), 0.0, 1e-12)
        << "a GL camera: right x up = -forward";
    for (int g = f + 1; g < kFaceCount; ++g)
      EXPECT_NEAR(glm::dot(a.axis, faces()[size_t(g)].axis), -1.0 / 3.0, 1e-12);
  }
}

TEST(Tetrahedron, EveryDirectionFallsInsideTheFrustumOfItsFace) {
  std::mt19937 rng(11);
  std::normal_distribution<double> n;
  for (int i = 0; i < 20000; ++i) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(n(rng), n(rng), n(rng)));
    const int f = direction_to_face(d);
    const Face& face = faces()[size_t(f)];
    const double along = glm::dot(d, face.axis);
    ASSERT_GT(along, 1.0 / 3.0 - 1e-12) << "within 70.53 degrees of its axis";
    const double x = glm::dot(d, face.right) / along, y = glm::dot(d, face.up) / along;
    EXPECT_GE(x, kLeft - 1e-9);
    EXPECT_LE(x, kRight + 1e-9);
    EXPECT_GE(y, kBottom - 1e-9);
    EXPECT_LE(y, kTop + 1e-9);
  }
  // The cell's corners (the other axes' antipodes) sit on the box: the frustum is as tight as a box can be.
  const Face& f0 = faces()[0];
  const glm::dvec3 corner = -faces()[1].axis;
  EXPECT_NEAR(glm::dot(corner, f0.up) / glm::dot(corner, f0.axis), kTop, 1e-12);
}

TEST(Tetrahedron, FaceMatricesLandEachTexelDirectionOnItsTexel) {
  const glm::vec3 light(0.5f, -1.0f, 2.0f);
  const int size = 96;
  for (cube::DepthRange range : {cube::DepthRange::minus_one_to_one, cube::DepthRange::zero_to_one})
    for (int f = 0; f < kFaceCount; ++f) {
      const glm::mat4 m = face_view_projection(f, light, 0.1f, 50.0f, range);
      for (double s : {0.5, 17.25, 48.0, 95.5})
        for (double t : {0.5, 30.75, 95.5}) {
          const glm::dvec3 d = face_point_direction(f, s, t, size);
          const glm::vec4 clip = m * glm::vec4(light + glm::vec3(d * 3.0), 1.0f);
          EXPECT_NEAR(clip.x / clip.w, 2.0 * s / size - 1.0, 1e-5) << "face " << f;
          EXPECT_NEAR(clip.y / clip.w, 2.0 * t / size - 1.0, 1e-5)
              << "face " << f << ": clip y = -1 on row 0";
          const double depth = clip.z / clip.w;
          EXPECT_LT(depth, 1.0);
          EXPECT_GT(depth, range == cube::DepthRange::zero_to_one ? 0.0 : -1.0);
        }
    }
  EXPECT_EQ(layer_size_for_cube(512), 627) << "4 x 627^2 = 1.572 M texels, a 512 cube's 1.573 M";
}

// The lighting pass's lookup (shaders/shadow_filters.glsl, LAYOUT_TETRAHEDRAL) states the bases in closed
// form, integer vectors times 1/sqrt 3, 1/sqrt 6 and 1/sqrt 2: read from the shader, they are faces()'s axes,
// ups and rights, so the lookup and the shadow pass's matrices agree on every face.
std::vector<glm::dvec3> shader_vectors(const std::string& text, const std::string& name) {
  const std::regex declaration("const vec3 " + name + R"(\[4\] = vec3\[\]\(([^;]*)\);)");
  std::smatch m;
  if (!std::regex_search(text, m, declaration)) return {};
  const std::string body = m[1];
  std::vector<glm::dvec3> out;
  const std::regex vec(R"(vec3\((-?\d+), (-?\d+), (-?\d+)\))");
  for (auto it = std::sregex_iterator(body.begin(), body.end(), vec); it != std::sregex_iterator(); ++it)
    out.emplace_back(std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3]));
  return out;
}

TEST(Tetrahedron, TheLookupsClosedFormBasesAreTheFaces) {
  std::ifstream file(std::string(OMNISHADOW_SHADERS_DIR) + "/shadow_filters.glsl");
  ASSERT_TRUE(file) << "shaders/shadow_filters.glsl";
  std::stringstream text;
  text << file.rdbuf();
  const std::vector<glm::dvec3> axes = shader_vectors(text.str(), "kTetraAxes");
  const std::vector<glm::dvec3> ups = shader_vectors(text.str(), "kTetraUps");
  const std::vector<glm::dvec3> rights = shader_vectors(text.str(), "kTetraRights");
  ASSERT_EQ(axes.size(), 4u);
  ASSERT_EQ(ups.size(), 4u);
  ASSERT_EQ(rights.size(), 4u);
  for (int f = 0; f < kFaceCount; ++f) {
    const Face& face = faces()[size_t(f)];
    EXPECT_NEAR(glm::length(axes[size_t(f)] / std::sqrt(3.0) - face.axis), 0.0, 1e-12) << "face " << f;
    EXPECT_NEAR(glm::length(ups[size_t(f)] / std::sqrt(6.0) - face.up), 0.0, 1e-12) << "face " << f;
    EXPECT_NEAR(glm::length(rights[size_t(f)] / std::sqrt(2.0) - face.right), 0.0, 1e-12) << "face " << f;
  }
}

}  // namespace
}  // namespace omnishadow::tetra
