// scenes/tessellate.h: n^2 triangles per triangle, the same surfaces (area and plane), the same winding,
// object ranges that follow, and vertices shared bit for bit along the edges two triangles shared (no
// cracks).
#include "scenes/tessellate.h"

#include <gtest/gtest.h>

#include <map>
#include <tuple>

namespace omnishadow::scene {
namespace {

Vertex v(float x, float y, float z) { return {{x, y, z}, {0, 0, 1}, {1, 1, 1}}; }

// Two triangles sharing the edge (1, 0, 0)-(0, 1, 0) with irrational-looking coordinates, and a second
// object.
Scene two_objects() {
  Scene s;
  s.name = "t";
  s.vertices = {v(0, 0, 0),       v(1.1f, 0.3f, 0), v(0.2f, 0.9f, 0), v(1.1f, 0.3f, 0), v(1.3f, 1.7f, 0.1f),
                v(0.2f, 0.9f, 0), v(5, 5, 5),       v(6, 5, 5),       v(5, 6.3f, 5)};
  s.objects = {{"a", "plane", 0, 6, false, {}, {}}, {"b", "plane", 6, 3, false, {}, {}}};
  return s;
}

double area(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  return 0.5 * glm::length(glm::cross(glm::dvec3(b - a), glm::dvec3(c - a)));
}

TEST(Tessellate, SameSurfacesInNSquaredTrianglesWithTheirWinding) {
  const Scene before = two_objects();
  for (int n : {1, 2, 5}) {
    Scene s = two_objects();
    tessellate(s, n);
    ASSERT_EQ(s.vertices.size(), before.vertices.size() * size_t(n * n));
    EXPECT_EQ(s.objects[0].first_vertex, 0u);
    EXPECT_EQ(s.objects[0].vertex_count, 6u * uint32_t(n * n));
    EXPECT_EQ(s.objects[1].first_vertex, 6u * uint32_t(n * n));
    for (size_t o = 0; o < 2; ++o) {
      const Object& was = before.objects[o];
      const Object& now = s.objects[o];
      double area_before = 0.0, area_after = 0.0;
      for (uint32_t i = was.first_vertex; i < was.first_vertex + was.vertex_count; i += 3)
        area_before += area(before.vertices[i].position, before.vertices[i + 1].position,
                            before.vertices[i + 2].position);
      const glm::vec3 normal = glm::normalize(glm::cross(
          before.vertices[was.first_vertex + 1].position - before.vertices[was.first_vertex].position,
          before.vertices[was.first_vertex + 2].position - before.vertices[was.first_vertex].position));
      for (uint32_t i = now.first_vertex; i < now.first_vertex + now.vertex_count; i += 3) {
        const glm::vec3 &a = s.vertices[i].position, &b = s.vertices[i + 1].position,
                        &c = s.vertices[i + 2].position;
        area_after += area(a, b, c);
        if (o == 1) {
          EXPECT_GT(glm::dot(glm::cross(b - a, c - a), normal), 0.0f) << "winding kept, n = " << n;
        }
      }
      EXPECT_NEAR(area_after, area_before, 1e-5 * area_before) << "object " << o << ", n = " << n;
    }
  }
}

// Every new vertex on the shared edge is produced by both triangles, bit for bit.
TEST(Tessellate, SharedEdgesShareTheirNewVerticesExactly) {
  Scene s = two_objects();
  const int n = 7;
  tessellate(s, n);
  const glm::vec3 p(1.1f, 0.3f, 0), q(0.2f, 0.9f, 0);
  std::map<std::tuple<float, float, float>, int> seen_by;  // vertex -> bit per source triangle
  for (uint32_t i = 0; i < s.objects[0].vertex_count; ++i) {
    const glm::vec3 x = s.vertices[i].position;
    const double off_edge =
        glm::length(glm::cross(glm::dvec3(x - p), glm::dvec3(q - p))) / glm::length(glm::dvec3(q - p));
    if (off_edge > 1e-5) continue;
    seen_by[{x.x, x.y, x.z}] |= i < 3u * n * n ? 1 : 2;
  }
  EXPECT_EQ(seen_by.size(), size_t(n + 1)) << "the edge's n + 1 points, each one vertex";
  for (const auto& [point, sources] : seen_by) EXPECT_EQ(sources, 3) << "made by both triangles";
}

TEST(Tessellate, RefusesNonsenseAndTooManyTriangles) {
  Scene s = two_objects();
  EXPECT_THROW(tessellate(s, 0), std::invalid_argument);
  s.vertices.resize(3 * 1000);
  try {
    tessellate(s, 200);  // 1000 x 40000 triangles
    FAIL() << "40 M triangles accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("scene t would have 40000000 triangles"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace omnishadow::scene
