#include "backends/common/view_culling.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "backends/common/layouts.h"
#include "backends/common/shadow_plan.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"

namespace omnishadow::cube {

ViewVolume camera_view(const scene::Camera& camera, int width, int height) {
  ViewVolume v;
  v.eye = camera.position;
  // glm::lookAtRH's basis: the camera looks along forward, right = forward x up.
  v.forward = glm::normalize(camera.target - camera.position);
  v.right = glm::normalize(glm::cross(v.forward, camera.up));
  v.up = glm::cross(v.right, v.forward);
  v.tan_half_y = std::tan(glm::radians(camera.fov_y_degrees) * 0.5f);
  v.tan_half_x = v.tan_half_y * static_cast<float>(width) / static_cast<float>(std::max(height, 1));
  v.near_plane = camera.near_plane;
  v.far_plane = camera.far_plane;
  return v;
}

namespace {

// A half-space n.q + d <= 0 with |n| = 1: a point beyond it by more than the margin is outside.
struct Plane {
  glm::vec3 n;
  float d;
  float distance(const glm::vec3& q) const { return glm::dot(n, q) + d; }
};

Plane plane_through(const glm::vec3& normal, const glm::vec3& point) {
  const glm::vec3 n = glm::normalize(normal);
  return {n, -glm::dot(n, point)};
}

// Every point of `points` lies beyond `p` by more than `margin`.
template <size_t N>
bool all_beyond(const Plane& p, const std::array<glm::vec3, N>& points, float margin) {
  return std::all_of(points.begin(), points.end(),
                     [&](const glm::vec3& q) { return p.distance(q) > margin; });
}

// The frustum's four sides (through the eye) and its near and far planes, the latter at depths z0 and z1.
std::array<Plane, 6> frustum_planes(const ViewVolume& v, float z0, float z1) {
  return {plane_through(v.right - v.tan_half_x * v.forward, v.eye),
          plane_through(-v.right - v.tan_half_x * v.forward, v.eye),
          plane_through(v.up - v.tan_half_y * v.forward, v.eye),
          plane_through(-v.up - v.tan_half_y * v.forward, v.eye),
          plane_through(-v.forward, v.eye + z0 * v.forward),
          plane_through(v.forward, v.eye + z1 * v.forward)};
}

std::array<glm::vec3, 8> frustum_corners(const ViewVolume& v, float z0, float z1) {
  std::array<glm::vec3, 8> c;
  for (int i = 0; i < 8; ++i) {
    const float z = (i & 4) ? z1 : z0;
    c[size_t(i)] = v.eye + z * v.forward + ((i & 1) ? 1.0f : -1.0f) * z * v.tan_half_x * v.right +
                   ((i & 2) ? 1.0f : -1.0f) * z * v.tan_half_y * v.up;
  }
  return c;
}

// Face f's directions from the light, widened by `slope` (1: the face exactly; the cube's face order +X, -X,
// +Y, -Y, +Z, -Z), cut at axis distance `depth`: the apex and the four corners of its far square.
std::array<glm::vec3, 5> face_pyramid(int face, const glm::vec3& light, float slope, float depth) {
  const int axis = face / 2;
  glm::vec3 a(0.0f), e1(0.0f), e2(0.0f);
  a[axis] = face % 2 == 0 ? 1.0f : -1.0f;
  e1[(axis + 1) % 3] = 1.0f;
  e2[(axis + 2) % 3] = 1.0f;
  std::array<glm::vec3, 5> p{light};
  for (int i = 0; i < 4; ++i)
    p[size_t(i + 1)] = light + depth * (a + slope * ((i & 1) ? e1 : -e1) + slope * ((i & 2) ? e2 : -e2));
  return p;
}

// The four sides of face f's widened direction cone: sigma (q - light)[other] - slope u(q) <= 0.
std::array<Plane, 4> face_cone_planes(int face, const glm::vec3& light, float slope) {
  const int axis = face / 2;
  glm::vec3 a(0.0f);
  a[axis] = face % 2 == 0 ? 1.0f : -1.0f;
  std::array<Plane, 4> planes;
  for (int i = 0; i < 4; ++i) {
    glm::vec3 side(0.0f);
    side[(axis + 1 + i / 2) % 3] = (i & 1) ? -1.0f : 1.0f;
    planes[size_t(i)] = plane_through(side - slope * a, light);
  }
  return planes;
}

}  // namespace

uint8_t view_face_mask(const ViewVolume& view, const glm::vec3& light, float range, const LookupReach& reach,
                       int face_size, bool per_face) {
  // Float tests on the CPU for positions the GPU interpolates: a relative 1e-4 in favour of keeping.
  const float scale = glm::length(light - view.eye) + range + 1.0f;
  const float margin = 1e-4f * scale;
  const float depth = glm::dot(light - view.eye, view.forward);
  const float z0 = std::max(view.near_plane, depth - range), z1 = std::min(view.far_plane, depth + range);
  if (z0 > z1 + margin) return 0;  // the range lies wholly before the near plane or beyond the far
  const std::array<Plane, 6> planes = frustum_planes(view, z0, z1);
  for (size_t i = 0; i < 4; ++i)
    if (planes[i].distance(light) > range + margin) return 0;  // the range sphere beyond one side
  if (!per_face || !reach.bounded) return kAllFaces;
  const std::array<glm::vec3, 8> corners = frustum_corners(view, z0, z1);
  // A face's edge is 1 in tangent units, half the face: `texels` texels are 2 texels / face_size.
  const float slope = 1.0f + 2.0f * reach.texels / float(std::max(face_size, 1));
  const float sample_margin = reach.world + margin;
  uint8_t mask = 0;
  for (int face = 0; face < 6; ++face) {
    bool separated = false;
    for (const Plane& p : face_cone_planes(face, light, slope))
      separated = separated || all_beyond(p, corners, sample_margin);
    // A sample lies within range + reach of the light: the cone's part up to that axis distance.
    const std::array<glm::vec3, 5> pyramid = face_pyramid(face, light, slope, range + reach.world + margin);
    for (const Plane& p : planes) separated = separated || all_beyond(p, pyramid, sample_margin);
    if (!separated) mask |= static_cast<uint8_t>(1u << face);
  }
  return mask;
}

}  // namespace omnishadow::cube

namespace omnishadow::gpu {

cube::LookupReach lookup_reach(const CaseConfig& c, float range, float camera_distance, int face_size) {
  cube::LookupReach reach;
  // Bilinear taps and seamless filtering read the neighbouring texel; the moments blur (5 taps, along s then
  // t) carries texels 2 + 2 away, past a seam on the unfolded cube.
  reach.texels = traits(c.filter).prefilter == Prefilter::separable_blur ? 6.0f : 2.0f;
  const float scale = c.pcf_scale, sqrt3 = std::sqrt(3.0f);
  // The normal-offset remedy looks up from 1.5 texels at the point's distance (< range) along its normal.
  const float shift = c.remedies.normal_offset ? 3.0f * range / float(std::max(face_size, 1)) : 0.0f;
  switch (c.filter) {
    case Filter::pcf_grid64:  // offsets -0.1 to 0.05 on each axis, times --pcf-scale
      reach.world = 0.1f * sqrt3 * scale;
      break;
    case Filter::pcf_disk20: {  // directions up to sqrt(3) long, radius (1 + view distance / far) / 25
      const float view_distance = camera_distance + range + shift;
      reach.world = sqrt3 * (1.0f + view_distance / range) / 25.0f * scale;
      break;
    }
    case Filter::pcss:  // the penumbra grows as the blocker nears the light, without bound
      reach.bounded = false;
      break;
    default:
      break;
  }
  reach.world += shift;
  return reach;
}

bool culls_faces_to_view(const CaseConfig& c) {
  if (traits(c.layout).geometry.map != TexelMap::cube_faces) return false;
  switch (traits(c.technique).culling) {
    case CullingForm::per_face_lists:
    case CullingForm::per_object_masks:
    case CullingForm::per_triangle_gs:
    case CullingForm::per_triangle_mask:
      return true;
    default:
      return false;  // multiview's views are the render pass's; mesh_shader's tasks cull by meshlet only
  }
}

uint8_t view_faces(const scene::Scene& scene, const CaseConfig& c, int frame, float range, int face_size) {
  if (!c.optimizations.view_culling || !scene.has_point_light()) return cube::kAllFaces;
  const glm::vec3 light = scene.light().path.at(frame);
  const scene::Camera camera = scene.camera.at(frame);
  const cube::LookupReach reach = lookup_reach(c, range, glm::length(camera.position - light), face_size);
  return cube::view_face_mask(cube::camera_view(camera, c.width, c.height), light, range, reach, face_size,
                              culls_faces_to_view(c));
}

}  // namespace omnishadow::gpu
