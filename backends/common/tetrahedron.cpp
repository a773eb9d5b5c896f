#include "backends/common/tetrahedron.h"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace omnishadow::tetra {

const std::array<Face, kFaceCount>& faces() {
  static const std::array<Face, kFaceCount> table = [] {
    const std::array<glm::dvec3, kFaceCount> axes = {
        glm::normalize(glm::dvec3(1, 1, 1)), glm::normalize(glm::dvec3(1, -1, -1)),
        glm::normalize(glm::dvec3(-1, 1, -1)), glm::normalize(glm::dvec3(-1, -1, 1))};
    std::array<Face, kFaceCount> out;
    for (int f = 0; f < kFaceCount; ++f) {
      const glm::dvec3 a = axes[size_t(f)], corner = -axes[size_t((f + 1) % kFaceCount)];
      const glm::dvec3 up = glm::normalize(corner - glm::dot(corner, a) * a);
      out[size_t(f)] = {a, glm::cross(a, up), up};
    }
    return out;
  }();
  return table;
}

int layer_size_for_cube(int cube_size) { return static_cast<int>(std::lround(cube_size * std::sqrt(1.5))); }

glm::mat4 face_view_projection(int face, const glm::vec3& light_position, float near_plane, float far_plane,
                               cube::DepthRange range) {
  const Face& f = faces()[size_t(face)];
  const glm::mat4 view = glm::lookAtRH(light_position, light_position + glm::vec3(f.axis), glm::vec3(f.up));
  const float n = near_plane;
  const glm::mat4 projection = range == cube::DepthRange::zero_to_one
                                   ? glm::frustumRH_ZO(float(kLeft) * n, float(kRight) * n,
                                                       float(kBottom) * n, float(kTop) * n, n, far_plane)
                                   : glm::frustumRH_NO(float(kLeft) * n, float(kRight) * n,
                                                       float(kBottom) * n, float(kTop) * n, n, far_plane);
  return projection * view;
}

int direction_to_face(const glm::dvec3& direction) {
  int best = 0;
  double best_dot = glm::dot(direction, faces()[0].axis);
  for (int f = 1; f < kFaceCount; ++f) {
    const double d = glm::dot(direction, faces()[size_t(f)].axis);
    if (d > best_dot) best = f, best_dot = d;
  }
  return best;
}

glm::dvec3 face_point_direction(int face, double s, double t, int size) {
  const Face& f = faces()[size_t(face)];
  const double x = kLeft + (kRight - kLeft) * s / size, y = kBottom + (kTop - kBottom) * t / size;
  return f.axis + x * f.right + y * f.up;
}

}  // namespace omnishadow::tetra
