#include "backends/common/shadow_plan.h"

#include <algorithm>
#include <cmath>

namespace omnishadow::cube {

uint8_t box_face_mask(const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& light, float near_plane,
                      float far_plane) {
  const glm::vec3 a = lo - light, b = hi - light;  // the box relative to the light
  // Margin in favour of drawing: the planes are tested in float on the CPU, the clipper works on the GPU's
  // transformed vertices; a relative 1e-4 keeps every borderline box.
  const float margin = 1e-4f * (std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z), std::fabs(b.x),
                                          std::fabs(b.y), std::fabs(b.z)}) +
                                1.0f);
  uint8_t mask = 0;
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2;
    const bool positive = face % 2 == 0;  // +X, -X, +Y, -Y, +Z, -Z
    // u: distance along the face axis, as the projection's near/far planes measure it.
    const float u_min = positive ? a[axis] : -b[axis];
    const float u_max = positive ? b[axis] : -a[axis];
    if (u_max < near_plane - margin || u_min > far_plane + margin) continue;
    bool outside = false;
    for (int other = 0; other < 3 && !outside; ++other) {
      if (other == axis) continue;
      // Inside the pyramid: -u <= v <= u. Beyond a side plane: every point has v > u, or every point v < -u.
      outside = u_max - a[other] < -margin || u_max + b[other] < -margin;
    }
    if (!outside) mask |= static_cast<uint8_t>(1u << face);
  }
  return mask;
}

uint8_t moved_caster_faces(const scene::Scene& scene, const glm::vec3& light, float near_plane,
                           float far_plane, int then, int now) {
  uint8_t faces = 0;
  for (const scene::Object& o : scene.objects) {
    if (!o.moves() || o.offset_at(then) == o.offset_at(now)) continue;
    faces |= box_face_mask(o.bounds_min_at(then), o.bounds_max_at(then), light, near_plane, far_plane);
    faces |= box_face_mask(o.bounds_min_at(now), o.bounds_max_at(now), light, near_plane, far_plane);
  }
  return faces;
}

ShadowDrawPlan plan_shadow_draws(const scene::Scene& scene, const glm::vec3& light, float near_plane,
                                 float far_plane, bool cull) {
  ShadowDrawPlan plan;
  plan.object_faces.resize(scene.objects.size(), kAllFaces);
  for (uint32_t i = 0; i < scene.objects.size(); ++i) {
    const scene::Object& o = scene.objects[i];
    if (cull) plan.object_faces[i] = box_face_mask(o.bounds_min, o.bounds_max, light, near_plane, far_plane);
    for (int face = 0; face < 6; ++face)
      if (plan.object_faces[i] & (1u << face)) plan.face_objects[face].push_back(i);
    if (plan.object_faces[i]) plan.reaching.push_back(i);
  }
  for (const auto& list : plan.face_objects) plan.empty_faces += list.empty();
  return plan;
}

void keep_faces(ShadowDrawPlan& plan, uint8_t faces) {
  if (faces == kAllFaces) return;
  for (int face = 0; face < 6; ++face)
    if (!(faces & (1u << face))) plan.face_objects[size_t(face)].clear();
  plan.reaching.clear();
  for (uint32_t i = 0; i < plan.object_faces.size(); ++i) {
    plan.object_faces[i] &= faces;
    if (plan.object_faces[i]) plan.reaching.push_back(i);
  }
  plan.empty_faces = 0;
  for (const auto& list : plan.face_objects) plan.empty_faces += list.empty();
}

float fitted_far(const scene::Scene& scene, const glm::vec3& light, float near_plane, float scene_far) {
  float farthest = 0.0f;
  for (const scene::Object& o : scene.objects)
    for (int corner = 0; corner < 8; ++corner) {
      glm::vec3 p((corner & 1) ? o.bounds_max.x : o.bounds_min.x,
                  (corner & 2) ? o.bounds_max.y : o.bounds_min.y,
                  (corner & 4) ? o.bounds_max.z : o.bounds_min.z);
      farthest = std::max(farthest, glm::length(p - light));
    }
  // The axis distance of a point never exceeds its distance, so the farthest corner bounds every face's
  // depth.
  return std::min(std::max(farthest * 1.001f, 2.0f * near_plane), scene_far);
}

}  // namespace omnishadow::cube
