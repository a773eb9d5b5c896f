// The BVH changes no answer: every ray the reference casts through its hierarchy (float boxes where provably
// conservative, double otherwise) gets exactly the answer of testing every triangle of the scene, including
// rays that graze vertices and edges lying on node boxes' faces, axis-parallel rays, and a scene far from the
// origin.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "backends/reference/ray_caster.h"

namespace omnishadow::reference {
namespace {

std::string json_vec(const glm::vec3& v) {
  return "[" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + "]";
}

// Spheres and rotated boxes over a floor; `offset` moves everything (the far-from-origin variant).
scene::Scene clutter(const glm::vec3& offset) {
  std::string objects = R"({"type": "plane", "scale": [10, 1, 10], "translate": )" + json_vec(offset) + "}";
  for (int i = 0; i < 12; ++i) {
    const glm::vec3 at = offset + glm::vec3(-5.7f + float(i), float(1 + i % 3), float((i * 7) % 9) - 3.9f);
    objects += R"(, {"type": ")" + std::string(i % 2 ? "box" : "sphere") + R"(", )" +
               (i % 2 ? "" : R"("segments": [16, 8], )") + R"("scale": 0.6, )" + R"("rotate": {"degrees": )" +
               std::to_string(i * 17) + R"(, "axis": [1, )" + std::to_string(i % 4) +
               R"(, 0.5]}, "translate": )" + json_vec(at) + "}";
  }
  const glm::vec3 light = offset + glm::vec3(0.0f, 6.0f, 0.0f);
  return scene::load_scene_text(
      R"({"light": {"position": )" + json_vec(light) + R"(, "far": 50}, "objects": [)" + objects + "]}",
      "clutter.json");
}

struct Segment {
  glm::vec3 from, to;
};

bool brute_blocked(const scene::Scene& s, const Segment& r, float eps) {
  const glm::dvec3 origin(r.from), segment = glm::dvec3(r.to) - origin;
  const double length = glm::length(segment);
  if (length <= 2.0 * eps) return false;
  const glm::dvec3 dir = segment / length;
  for (size_t i = 0; i + 2 < s.vertices.size(); i += 3) {
    const glm::dvec3 a(s.vertices[i].position), b(s.vertices[i + 1].position), c(s.vertices[i + 2].position);
    const double d = intersect(origin, dir, a, b - a, c - a, nullptr, nullptr);
    if (d > eps && d < length - eps) return true;
  }
  return false;
}

// The nearest hit's distance and triangle (the lowest index of those at that distance); -1 for none.
std::pair<double, uint32_t> brute_closest(const scene::Scene& s, const glm::vec3& origin,
                                          const glm::vec3& dir, double max_distance) {
  double best = -1.0;
  uint32_t triangle = 0;
  for (size_t i = 0; i + 2 < s.vertices.size(); i += 3) {
    const glm::dvec3 a(s.vertices[i].position), b(s.vertices[i + 1].position), c(s.vertices[i + 2].position);
    const double d = intersect(glm::dvec3(origin), glm::dvec3(dir), a, b - a, c - a, nullptr, nullptr);
    if (d > 0.0 && d < max_distance) {
      best = d;
      triangle = uint32_t(i / 3);
      max_distance = d;
    }
  }
  return {best, triangle};
}

// Rays from the light through vertices, edge midpoints and centroids (each point mid-segment, so that it lies
// inside the ray's reach on a node box's face) and ending just short of them, and axis-parallel and almost
// axis-parallel rays through vertices.
std::vector<Segment> grazing_rays(const scene::Scene& s, const glm::vec3& light, size_t step) {
  std::vector<Segment> rays;
  for (size_t i = 0; i + 2 < s.vertices.size(); i += 3 * step) {
    const glm::vec3 a = s.vertices[i].position, b = s.vertices[i + 1].position,
                    c = s.vertices[i + 2].position;
    for (const glm::vec3& p : {a, 0.5f * (a + b), (a + b + c) / 3.0f}) {
      rays.push_back({light, p + 0.5f * (p - light)});        // through p
      rays.push_back({light, light + 0.999f * (p - light)});  // ending just short of p
    }
    for (int axis = 0; axis < 3; ++axis) {
      glm::vec3 along(0.0f);
      along[axis] = 3.0f;
      rays.push_back({a - along, a + along});  // exactly parallel: the double boxes
      glm::vec3 tilt = along;
      tilt[(axis + 1) % 3] = 3e-12f;  // below the float path's 1e-12 limit after normalising
      rays.push_back({a - tilt, a + tilt});
      tilt[(axis + 1) % 3] = 3e-6f;  // just above it: float boxes with an almost parallel ray
      rays.push_back({a - tilt, a + tilt});
    }
  }
  return rays;
}

void expect_same_answers(const scene::Scene& s, const glm::vec3& light) {
  RayCaster caster(s);
  int blocked = 0, clear = 0, hits = 0;
  for (const Segment& r : grazing_rays(s, light, 3)) {
    const bool expected = brute_blocked(s, r, 1e-4f);
    ASSERT_EQ(caster.blocked(r.from, r.to, 1e-4f), expected)
        << "from (" << r.from.x << ", " << r.from.y << ", " << r.from.z << ") to (" << r.to.x << ", "
        << r.to.y << ", " << r.to.z << ")";
    (expected ? blocked : clear) += 1;
    const glm::vec3 dir = glm::normalize(r.to - r.from);
    const double length = glm::length(glm::dvec3(r.to) - glm::dvec3(r.from));
    const auto [exact, triangle] = brute_closest(s, r.from, dir, length);
    const Hit h = caster.closest(r.from, dir, length);
    ASSERT_EQ(h.hit, exact > 0.0) << "closest from (" << r.from.x << ", " << r.from.y << ", " << r.from.z
                                  << ")";
    if (h.hit) {
      EXPECT_EQ(h.distance, exact);
      EXPECT_EQ(h.triangle, triangle) << "ties go to the lowest index";
    }
    hits += h.hit;
  }
  EXPECT_GT(blocked, 500);
  EXPECT_GT(clear, 500);
  EXPECT_GT(hits, 500);
}

TEST(RayCasterBvh, AnswersAsEveryTriangleTestedOnGrazingRays) {
  expect_same_answers(clutter(glm::vec3(0.0f)), {0.0f, 6.0f, 0.0f});
}

TEST(RayCasterBvh, AnswersAsEveryTriangleTestedFarFromTheOrigin) {
  // 1e5 away: a float's spacing there (0.0078) is larger than the end tolerance, the case the widening is
  // for.
  expect_same_answers(clutter({1e5f, 0.0f, 1e5f}), {1e5f, 6.0f, 1e5f});
}

}  // namespace
}  // namespace omnishadow::reference
