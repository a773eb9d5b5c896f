#include "backends/common/paraboloid.h"

#include <cmath>

namespace omnishadow::paraboloid {

int layer_size_for_cube(int cube_size) { return static_cast<int>(std::lround(cube_size * std::sqrt(3.0))); }

LayerCoord direction_to_layer(const glm::dvec3& direction) {
  const glm::dvec3 d = glm::normalize(direction);
  const int layer = d.z >= 0.0 ? 0 : 1;
  const double a = layer == 0 ? 1.0 : -1.0;
  const double f = a * d.z;
  return {layer, -a * d.x / (1.0 + f), d.y / (1.0 + f)};
}

// The inverse of (x, y) = (vx, vy) / (1 + f) on the unit sphere: with r^2 = x^2 + y^2,
// (vx, vy, f) = (2x, 2y, 1 - r^2) / (1 + r^2).
glm::dvec3 layer_point_direction(int layer, double x, double y) {
  const double a = layer == 0 ? 1.0 : -1.0;
  const double r2 = x * x + y * y;
  const double vx = 2.0 * x / (1.0 + r2), vy = 2.0 * y / (1.0 + r2), f = (1.0 - r2) / (1.0 + r2);
  return {-a * vx, vy, a * f};
}

glm::dvec3 texel_point_direction(int layer, double s, double t, int size) {
  return layer_point_direction(layer, 2.0 * s / size - 1.0, 2.0 * t / size - 1.0);
}

bool texel_in_disk(int s, int t, int size) {
  const double x = 2.0 * (s + 0.5) / size - 1.0, y = 2.0 * (t + 0.5) / size - 1.0;
  return x * x + y * y <= 1.0;
}

}  // namespace omnishadow::paraboloid
