#include "backends/common/map_lights.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace omnishadow::gpu {

glm::vec3 map_up(const glm::vec3& direction) {
  return std::fabs(direction.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
}

glm::mat4 map_view_projection(const scene::Scene& scene, const scene::MapLight& light, int frame,
                              cube::DepthRange range) {
  const bool zo = range == cube::DepthRange::zero_to_one;
  if (light.type == scene::MapLightType::spot) {
    glm::vec3 position = light.path.at(frame);
    glm::mat4 view = glm::lookAtRH(position, position + light.direction, map_up(light.direction));
    float fov = glm::radians(light.cone_degrees);
    glm::mat4 proj = zo ? glm::perspectiveRH_ZO(fov, 1.0f, light.near_plane, light.far_plane)
                        : glm::perspectiveRH_NO(fov, 1.0f, light.near_plane, light.far_plane);
    return proj * view;
  }
  // Directional: look along the direction from the scene's centre; fit x, y and depth to every bounds corner.
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const scene::Object& o : scene.objects) {
    lo = glm::min(lo, o.bounds_min);
    hi = glm::max(hi, o.bounds_max);
  }
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = std::max(glm::length(hi - lo) * 0.5f, 1e-3f);
  glm::mat4 view = glm::lookAtRH(centre - light.direction * (2.0f * radius), centre, map_up(light.direction));
  glm::vec3 vlo(INFINITY), vhi(-INFINITY);
  for (int corner = 0; corner < 8; ++corner) {
    glm::vec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
    glm::vec3 v = glm::vec3(view * glm::vec4(p, 1.0f));
    vlo = glm::min(vlo, v);
    vhi = glm::max(vhi, v);
  }
  const glm::vec3 margin = 0.01f * (vhi - vlo) + glm::vec3(1e-4f);
  vlo -= margin;
  vhi += margin;
  // View space looks down -z: near = -vhi.z, far = -vlo.z.
  glm::mat4 proj = zo ? glm::orthoRH_ZO(vlo.x, vhi.x, vlo.y, vhi.y, -vhi.z, -vlo.z)
                      : glm::orthoRH_NO(vlo.x, vhi.x, vlo.y, vhi.y, -vhi.z, -vlo.z);
  return proj * view;
}

}  // namespace omnishadow::gpu
