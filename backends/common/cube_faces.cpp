#include "backends/common/cube_faces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>

#include "backends/common/storage_filter_tables.h"

namespace omnishadow::cube {

float projective_depth_to_distance(float window_depth, int s, int t, int size, float near_plane,
                                   float far_plane, DepthRange range) {
  if (window_depth >= 1.0f) return far_plane;
  const double n = near_plane, f = far_plane, d = window_depth;
  const double axis = range == DepthRange::zero_to_one ? n * f / (f - d * (f - n))
                                                       : 2.0 * n * f / (f + n - (2.0 * d - 1.0) * (f - n));
  const double u = 2.0 * (s + 0.5) / size - 1.0, v = 2.0 * (t + 0.5) / size - 1.0;
  return static_cast<float>(axis * std::sqrt(1.0 + u * u + v * v));
}

glm::mat4 face_projection(float near_plane, float far_plane, DepthRange range) {
  glm::mat4 p = glm::perspectiveRH_NO(glm::radians(90.0f), 1.0f, near_plane, far_plane);
  if (range == DepthRange::zero_to_one)
    p = glm::perspectiveRH_ZO(glm::radians(90.0f), 1.0f, near_plane, far_plane);
  return p;
}

glm::mat4 face_view(int face, const glm::vec3& light_position) {
  return glm::lookAtRH(light_position, light_position + kFaceDirections[face], kFaceUps[face]);
}

std::array<glm::mat4, kFaceCount> face_view_projections(const glm::vec3& light_position, float near_plane,
                                                        float far_plane, DepthRange range) {
  glm::mat4 projection = face_projection(near_plane, far_plane, range);
  std::array<glm::mat4, kFaceCount> out;
  for (int f = 0; f < kFaceCount; ++f) out[f] = projection * face_view(f, light_position);
  return out;
}

float stored_to_distance(Storage storage, float stored, int s, int t, int size, float near_plane,
                         float far_plane, DepthRange range) {
  switch (traits(storage).checked) {
    case DistanceEncoding::linear_depth:
      return stored * far_plane;
    case DistanceEncoding::colour_distance:
      return stored;
    case DistanceEncoding::projective_depth:
      return projective_depth_to_distance(stored, s, t, size, near_plane, far_plane, range);
  }
  return stored;
}

glm::vec3 texel_direction(int face, int s, int t, int size) {
  // Table 8.19 inverted: s = (sc / |ma| + 1) / 2, t = (tc / |ma| + 1) / 2 at the texel centre.
  const float u = 2.0f * (float(s) + 0.5f) / float(size) - 1.0f,
              v = 2.0f * (float(t) + 0.5f) / float(size) - 1.0f;
  switch (face) {
    case 0:
      return {1.0f, -v, -u};  // +X: sc = -rz, tc = -ry
    case 1:
      return {-1.0f, -v, u};  // -X: sc = +rz, tc = -ry
    case 2:
      return {u, 1.0f, v};  // +Y: sc = +rx, tc = +rz
    case 3:
      return {u, -1.0f, -v};  // -Y: sc = +rx, tc = -rz
    case 4:
      return {u, -v, 1.0f};  // +Z: sc = +rx, tc = -ry
    default:
      return {-u, -v, -1.0f};  // -Z: sc = -rx, tc = -ry
  }
}

glm::dvec3 face_point_direction(int face, double s, double t, int size) {
  // As texel_direction, in double and at any point: the truth's rays a sub-pixel step off a centre differ
  // from the centre's by ~1e-5 of a face, which float would round away at large sizes.
  const double u = 2.0 * s / double(size) - 1.0, v = 2.0 * t / double(size) - 1.0;
  switch (face) {
    case 0:
      return {1.0, -v, -u};
    case 1:
      return {-1.0, -v, u};
    case 2:
      return {u, 1.0, v};
    case 3:
      return {u, -1.0, -v};
    case 4:
      return {u, -v, 1.0};
    default:
      return {-u, -v, -1.0};
  }
}

FaceTexel neighbour_texel(int face, int s, int t, int axis, int k, int size) {
  (axis == 0 ? s : t) += k;
  if (s >= 0 && s < size && t >= 0 && t < size) return {face, s, t};
  // The texel centre in half-texel units on a cube of half-extent `size` (Table 8.19's placement of sc and
  // tc).
  const int u = 2 * s + 1 - size, v = 2 * t + 1 - size;
  std::array<int, 3> p;
  switch (face) {
    case 0:
      p = {size, -v, -u};
      break;
    case 1:
      p = {-size, -v, u};
      break;
    case 2:
      p = {u, size, v};
      break;
    case 3:
      p = {u, -size, -v};
      break;
    case 4:
      p = {u, -v, size};
      break;
    default:
      p = {-u, -v, -size};
      break;
  }
  // Fold the coordinate that left the face onto the adjacent face's major axis; the old major axis shrinks by
  // the excess (the unfolded cube).
  const int major = face / 2;
  int beyond = major == 0 ? 1 : 0;
  for (int c = 0; c < 3; ++c)
    if (c != major && std::abs(p[c]) > size) beyond = c;
  const int excess = std::abs(p[beyond]) - size;
  p[major] = (p[major] > 0 ? 1 : -1) * (size - excess);
  p[beyond] = p[beyond] > 0 ? size : -size;
  const int to = 2 * beyond + (p[beyond] > 0 ? 0 : 1);
  const int x = p[0], y = p[1], z = p[2];
  const int sc = to == 0 ? -z : to == 1 ? z : to == 5 ? -x : x;
  const int tc = to == 2 ? z : to == 3 ? -z : -y;
  return {to, (sc + size - 1) / 2, (tc + size - 1) / 2};
}

uint8_t faces_within(const glm::vec3& d, float texels, int face_size) {
  const float slope = 1.0f + 2.0f * texels / float(std::max(face_size, 1));
  uint8_t mask = 0;
  for (int f = 0; f < kFaceCount; ++f) {
    const int axis = f / 2;
    const float u = (f % 2 == 0 ? 1.0f : -1.0f) * d[axis];
    if (u > 0.0f && std::fabs(d[(axis + 1) % 3]) <= slope * u && std::fabs(d[(axis + 2) % 3]) <= slope * u)
      mask |= uint8_t(1u << f);
  }
  return mask;
}

FaceCoord direction_to_face(const glm::vec3& d) {
  glm::vec3 a = glm::abs(d);
  int face;
  float sc, tc, ma;
  if (a.x >= a.y && a.x >= a.z) {
    face = d.x >= 0 ? 0 : 1;
    ma = a.x;
    sc = d.x >= 0 ? -d.z : d.z;
    tc = -d.y;
  } else if (a.y >= a.z) {
    face = d.y >= 0 ? 2 : 3;
    ma = a.y;
    sc = d.x;
    tc = d.y >= 0 ? d.z : -d.z;
  } else {
    face = d.z >= 0 ? 4 : 5;
    ma = a.z;
    sc = d.z >= 0 ? d.x : -d.x;
    tc = -d.y;
  }
  return {face, 0.5f * (sc / ma + 1.0f), 0.5f * (tc / ma + 1.0f)};
}

}  // namespace omnishadow::cube
