#include "backends/reference/ray_caster.h"

#include <cmath>

namespace omnishadow::reference {

RayCaster::RayCaster(const scene::Scene& scene) {
  triangles_.reserve(scene.vertices.size() / 3);
  for (size_t i = 0; i + 2 < scene.vertices.size(); i += 3) {
    const glm::vec3 a = scene.vertices[i].position;
    triangles_.push_back({a, scene.vertices[i + 1].position - a, scene.vertices[i + 2].position - a});
  }
}

bool RayCaster::blocked(const glm::vec3& light, const glm::vec3& point, float end_epsilon) const {
  // Moller-Trumbore in double precision: the answer must not depend on float rounding near edges.
  const glm::dvec3 origin(light);
  const glm::dvec3 segment = glm::dvec3(point) - origin;
  const double length = glm::length(segment);
  if (length <= 2.0 * end_epsilon) return false;
  const glm::dvec3 dir = segment / length;
  for (const Triangle& t : triangles_) {
    const glm::dvec3 e1(t.e1), e2(t.e2);
    const glm::dvec3 p = glm::cross(dir, e2);
    const double det = glm::dot(e1, p);
    if (std::fabs(det) < 1e-14) continue;  // parallel (both sides: casters are not culled for visibility)
    const double inv = 1.0 / det;
    const glm::dvec3 s = origin - glm::dvec3(t.a);
    const double u = glm::dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) continue;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(dir, q) * inv;
    if (v < 0.0 || u + v > 1.0) continue;
    const double distance = glm::dot(e2, q) * inv;
    if (distance > end_epsilon && distance < length - end_epsilon) return true;
  }
  return false;
}

}  // namespace omnishadow::reference
