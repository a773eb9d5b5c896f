// The CPU side of per-face culling and range fitting (backends/common/shadow_plan.h): conservative by
// construction, so checked against brute force on random boxes.
#include "backends/common/shadow_plan.h"

#include <gtest/gtest.h>

#include <random>

#include "backends/common/cube_faces.h"
#include "scenes/scene.h"

namespace omnishadow::cube {
namespace {

TEST(ShadowPlan, BoxesLandOnTheFacesTheyFace) {
  const glm::vec3 light(0.0f);
  EXPECT_EQ(box_face_mask({2, -0.5f, -0.5f}, {3, 0.5f, 0.5f}, light, 0.1f, 25), 1u << 0);    // +X only
  EXPECT_EQ(box_face_mask({-0.5f, -3, -0.5f}, {0.5f, -2, 0.5f}, light, 0.1f, 25), 1u << 3);  // -Y only
  EXPECT_EQ(box_face_mask({-1, -1, -1}, {1, 1, 1}, light, 0.1f, 25), kAllFaces) << "the light inside the box";
  EXPECT_EQ(box_face_mask({30, -1, -1}, {31, 1, 1}, light, 0.1f, 25), 0u) << "beyond far";
  EXPECT_EQ(box_face_mask({0.01f, -0.01f, -0.01f}, {0.05f, 0.01f, 0.01f}, light, 0.1f, 25), 0u)
      << "before near";
  // A box across the +X/+Y edge reaches both.
  EXPECT_EQ(box_face_mask({2, 2, -0.1f}, {3, 3, 0.1f}, light, 0.1f, 25), (1u << 0) | (1u << 2));
}

// Brute force: sample points in random boxes; any point inside a face's frustum must have that face's bit.
TEST(ShadowPlan, MaskNeverDropsAFaceAPointOfTheBoxReaches) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-10, 10), size(0.01f, 4), unit(0, 1);
  const glm::vec3 light(0.3f, -0.2f, 0.1f);
  const float near_plane = 0.5f, far_plane = 12.0f;
  int checked = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    glm::vec3 lo(pos(rng), pos(rng), pos(rng));
    glm::vec3 hi = lo + glm::vec3(size(rng), size(rng), size(rng));
    uint8_t mask = box_face_mask(lo, hi, light, near_plane, far_plane);
    for (int s = 0; s < 64; ++s) {
      glm::vec3 p = lo + (hi - lo) * glm::vec3(unit(rng), unit(rng), unit(rng));
      glm::vec3 d = p - light;
      for (int face = 0; face < 6; ++face) {
        int axis = face / 2;
        float u = face % 2 == 0 ? d[axis] : -d[axis];
        bool inside = u >= near_plane && u <= far_plane;
        for (int other = 0; other < 3; ++other)
          if (other != axis) inside = inside && std::fabs(d[other]) <= u;
        if (inside) {
          ++checked;
          ASSERT_TRUE(mask & (1u << face))
              << "face " << face << " dropped for a box it reaches (trial " << trial << ")";
        }
      }
    }
  }
  EXPECT_GT(checked, 10000);
}

TEST(ShadowPlan, FittedFarBoundsEveryVertexAndNeverExceedsTheScene) {
  scene::Scene s = scene::load_scene_text(R"({"light": {"near": 0.5, "far": 100},
      "objects": [{"type": "box", "scale": 5, "inside": true}, {"type": "sphere", "translate": [2, 1, 0]}]})",
                                          "inline.json");
  for (glm::vec3 light : {glm::vec3(0), glm::vec3(1, 2, 3), glm::vec3(-4.9f, 0, 0)}) {
    float far_plane = fitted_far(s, light, 0.5f, 100.0f);
    float farthest = 0.0f;
    for (const scene::Vertex& v : s.vertices) farthest = std::max(farthest, glm::length(v.position - light));
    EXPECT_GE(far_plane, farthest) << "light " << light.x << "," << light.y << "," << light.z;
    EXPECT_LE(far_plane, 2.0f * std::sqrt(3.0f) * 5.0f + 0.1f);
  }
  EXPECT_EQ(fitted_far(s, glm::vec3(0), 0.5f, 3.0f), 3.0f) << "a scene's far is an upper bound";
}

TEST(ShadowPlan, UnculledPlanDrawsEverythingEverywhere) {
  scene::Scene s = scene::load_scene_text(R"({"light": {}, "objects": [{"type": "box"}, {"type": "plane"}]})",
                                          "inline.json");
  ShadowDrawPlan plan = plan_shadow_draws(s, glm::vec3(10, 0, 0), 1, 25, false);
  for (const auto& list : plan.face_objects) EXPECT_EQ(list.size(), 2u);
  EXPECT_EQ(plan.empty_faces, 0);
  ShadowDrawPlan culled = plan_shadow_draws(s, glm::vec3(10, 0, 0), 1, 25, true);
  EXPECT_EQ(culled.face_objects[1].size(), 2u) << "both lie towards -X of the light";
  EXPECT_GE(culled.empty_faces, 1);
}

}  // namespace
}  // namespace omnishadow::cube
