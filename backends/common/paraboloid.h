#pragma once
// Dual-paraboloid conventions (layout dual_paraboloid): the one source of truth for the texel <->
// direction map, used by the truths and the tests; shaders/paraboloid.glsl is the same arithmetic in GLSL
// (warp in the shadow pass, lookup in the lighting pass): change both together.
//
// Two layers around the light: layer 0 sees the hemisphere z >= 0 (world +Z from the light), layer 1 z < 0.
// Each is looked at as by a GL camera along its axis with +Y up (layer 1 is the camera's own -Z view; layer 0
// turns it half a turn about Y, so its window x is world -X), which keeps triangles' winding as the cube
// faces' cameras do. A unit direction d with forward component f = a d.z (a = +1 for layer 0, -1 for layer 1)
// lands at window coordinates
//   x = -a d.x / (1 + f),  y = d.y / (1 + f)        (Heidrich and Seidel's paraboloid, in [-1, 1]^2)
// inside the unit disk (f >= 0); the equator (f = 0) is the unit circle. As the cube faces: clip y = -1 on
// the first row in memory, texel column s grows with x and row t with y. Depth is linear in the distance from
// the light: (distance - near) / (far - near), with w = 1, so nothing is perspective-divided.

#include <array>
#include <glm/glm.hpp>

namespace omnishadow::paraboloid {

inline constexpr int kLayerCount = 2;
inline constexpr std::array<const char*, kLayerCount> kLayerNames = {"+Z half", "-Z half"};

// Layer size for a layout at the memory of a cube of `cube_size` (6 cube_size^2 texels): 2 S^2 = 6 N^2.
int layer_size_for_cube(int cube_size);

struct LayerCoord {
  int layer;
  double x, y;  // window coordinates in [-1, 1] (inside the unit disk)
};
// Which layer a direction selects (z >= 0: layer 0) and where in it; the lighting pass's lookup.
LayerCoord direction_to_layer(const glm::dvec3& direction);

// The unit direction through window point (x, y) of a layer; points outside the unit disk (r > 1) have no
// direction of their own hemisphere and return the mirror image beyond the equator (f < 0), which no lookup
// reads.
glm::dvec3 layer_point_direction(int layer, double x, double y);
// The same in continuous texel coordinates of a layer of `size` (texel k's centre at k + 0.5).
glm::dvec3 texel_point_direction(int layer, double s, double t, int size);
// Whether texel (s, t)'s centre lies inside the unit disk: the texels a lookup can read.
bool texel_in_disk(int s, int t, int size);

}  // namespace omnishadow::paraboloid
