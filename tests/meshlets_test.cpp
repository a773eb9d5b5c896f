// mesh_shader's meshlets (backends/common/meshlets.h): together they hold every triangle of every object
// exactly once, in the scene's winding (a rotation of its vertices, never a reflection, so back-face culling
// is unchanged), within the mesh stage's limits; each object's meshlets start on a task group and its spheres
// contain its vertices.
#include "backends/common/meshlets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <string>

#include "scenes/scene.h"

namespace omnishadow::gpu {
namespace {

using Triangle = std::array<std::array<float, 3>, 3>;

// A triangle by its positions, rotated so that its least vertex comes first: equal for rotations of one
// winding, different for the reflected winding.
Triangle canonical(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  std::array<std::array<float, 3>, 3> t = {{{a.x, a.y, a.z}, {b.x, b.y, b.z}, {c.x, c.y, c.z}}};
  const size_t least = static_cast<size_t>(std::min_element(t.begin(), t.end()) - t.begin());
  std::rotate(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(least), t.end());
  return t;
}

void expect_meshlets_hold_the_scene(const scene::Scene& s) {
  const MeshletData m = build_meshlets(s);
  ASSERT_EQ(m.objects.size(), s.objects.size());
  EXPECT_EQ(m.meshlets.size() % kMeshletsPerTask, 0u);
  EXPECT_EQ(m.spheres.size(), m.meshlets.size());
  for (size_t o = 0; o < s.objects.size(); ++o) {
    const scene::Object& obj = s.objects[o];
    std::map<Triangle, int> expected, got;
    for (uint32_t i = 0; i + 2 < obj.vertex_count; i += 3) {
      const auto& v = s.vertices;
      ++expected[canonical(v[obj.first_vertex + i].position, v[obj.first_vertex + i + 1].position,
                           v[obj.first_vertex + i + 2].position)];
    }
    const ObjectMeshlets& om = m.objects[o];
    if (o > 0) {
      EXPECT_EQ(om.first_task, m.objects[o - 1].first_task + m.objects[o - 1].task_count);
    }
    for (uint32_t k = om.first_task * kMeshletsPerTask;
         k < (om.first_task + om.task_count) * kMeshletsPerTask; ++k) {
      const Meshlet& ml = m.meshlets[k];
      ASSERT_LE(ml.vertex_count, kMaxMeshletVertices);
      ASSERT_LE(ml.triangle_count, kMaxMeshletTriangles);
      for (uint32_t v = 0; v < ml.vertex_count; ++v) {
        const uint32_t index = m.vertices[ml.vertex_offset + v];
        ASSERT_GE(index, obj.first_vertex) << "a meshlet reads its own object's vertices";
        ASSERT_LT(index, obj.first_vertex + obj.vertex_count);
        const glm::vec3 p = s.vertices[index].position;
        EXPECT_LE(glm::length(glm::dvec3(p) - glm::dvec3(glm::vec3(m.spheres[k]))), double(m.spheres[k].w))
            << "object " << o << " meshlet " << k;
      }
      for (uint32_t t = 0; t < ml.triangle_count; ++t) {
        const uint32_t packed = m.triangles[ml.triangle_offset + t];
        glm::vec3 corner[3];
        for (int c = 0; c < 3; ++c) {
          const uint32_t local = (packed >> (8 * c)) & 0xFFu;
          ASSERT_LT(local, ml.vertex_count);
          corner[c] = s.vertices[m.vertices[ml.vertex_offset + local]].position;
        }
        ++got[canonical(corner[0], corner[1], corner[2])];
      }
    }
    EXPECT_EQ(got, expected) << "object " << o << " (" << obj.name
                             << "): every triangle once, in its winding";
  }
}

TEST(Meshlets, HoldEveryTriangleOnceInItsWindingWithinTheLimits) {
  for (const char* name : {"room.json", "heavy.json", "mixed.json"}) {
    SCOPED_TRACE(name);
    expect_meshlets_hold_the_scene(
        scene::load_scene_file(std::string(OMNISHADOW_TEST_SCENES_DIR) + "/" + name));
  }
}

// A backend's scene copy holds no vertices once they are on the device (Backend::load): meshlets built from
// it would read past the end (a SIGSEGV on the first mesh_shader case on NVIDIA, the first device that ran
// one). Building refuses such a scene by name instead; backends build their meshlets in load(), before the
// release.
TEST(Meshlets, ASceneWithoutItsVerticesIsRefusedByName) {
  scene::Scene s = scene::load_scene_file(std::string(OMNISHADOW_TEST_SCENES_DIR) + "/room.json");
  s.vertices.clear();
  try {
    (void)build_meshlets(s);
    FAIL() << "meshlets built from a scene without vertices";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("reaches past the scene's 0 vertices"), std::string::npos)
        << e.what();
  }
}

TEST(Meshlets, AReflectedTriangleIsNotTheSameTriangle) {
  // The check above would miss a winding flip if canonical() ignored orientation: it must not.
  const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(canonical(a, b, c), canonical(b, c, a));
  EXPECT_NE(canonical(a, b, c), canonical(a, c, b));
}

// A size the device cannot launch is refused with the limit's name and value, never launched: natively per
// object (the largest object's task workgroups, times the lights of one pass), emulated for the whole scene.
TEST(Meshlets, LaunchesBeyondTheDevicesLimitsAreRefusedByName) {
  MeshletData m;
  m.meshlets.resize(size_t(5) * kMeshletsPerTask);
  m.objects = {{0, 2}, {2, 3}};  // task groups 0-1 and 2-4
  EXPECT_EQ(mesh_launch_refusal(m, 1, false, 3, "L", 5, "D"), "");
  EXPECT_EQ(
      mesh_launch_refusal(m, 4, false, 11, "L", 5, "D"),
      "mesh_shader launches an object's 12 task workgroups (meshlet groups x 4 lights) at once, above L 11");
  EXPECT_EQ(mesh_launch_refusal(m, 4, false, 12, "L", 5, "D"), "");
  EXPECT_EQ(mesh_launch_refusal(m, 1, true, 0, "L", 5, "D"), "");
  EXPECT_EQ(mesh_launch_refusal(m, 2, true, 0, "L", 9, "D"),
            "mesh_shader's emulation dispatches the scene's 10 task workgroups (meshlet groups x 2 lights) "
            "at once, "
            "above D 9");
}

}  // namespace
}  // namespace omnishadow::gpu
