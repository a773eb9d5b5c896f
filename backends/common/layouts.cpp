#include "backends/common/layouts.h"

#include <cmath>

namespace omnishadow::layout_geometry {

int cube_layer_size(int cube_size) { return cube_size; }

// A perspective face's ray: its near and far are axis distances, and the direction's axis component is 1, so
// its length is distance over axis distance.
static LayerRay perspective_ray(const glm::dvec3& d) {
  const double len = glm::length(d);
  return {d / len, len};
}

std::optional<LayerRay> cube_point_ray(int layer, double s, double t, int size) {
  return perspective_ray(cube::face_point_direction(layer, s, t, size));
}

std::optional<LayerRay> tetrahedral_point_ray(int layer, double s, double t, int size) {
  return perspective_ray(tetra::face_point_direction(layer, s, t, size));
}

// A layer clips the other hemisphere (forward < 0: outside the unit disk), and its near and far are radial.
std::optional<LayerRay> paraboloid_point_ray(int layer, double s, double t, int size) {
  const glm::dvec3 d = paraboloid::texel_point_direction(layer, s, t, size);
  if ((layer == 0 ? d.z : -d.z) < 0.0) return std::nullopt;
  return LayerRay{d, 1.0};
}

bool every_texel(int, int, int) { return true; }

glm::mat4 cube_view_projection(int layer, const glm::vec3& light, float near_plane, float far_plane,
                               cube::DepthRange range) {
  // One face's matrix only (face_view_projections' product for that face): the frame uniforms ask per layer.
  return cube::face_projection(near_plane, far_plane, range) * cube::face_view(layer, light);
}

}  // namespace omnishadow::layout_geometry
