#pragma once
// The one source of truth for cube-map conventions, used by every backend, the reference and the tests.
//
// Face order is the GL/Vulkan layer order +X, -X, +Y, -Y, +Z, -Z (the point-shadow tutorial: "right, left,
// top, bottom, near, far"), with the tutorial's up vectors. Those up vectors make a face rendered with lookAt
// + a 90-degree perspective land in memory exactly as cube-map sampling (GL 4.5 spec table 8.19, same table
// in Vulkan) reads it: texel column s grows with window x, texel row t grows with window y, and row 0 is the
// first row in memory.
//
// Clip conventions: GL maps depth to [-1, 1], Vulkan to [0, 1]. Both put clip y = -1 on the first row in
// memory, so a cube face needs no y flip in either API; only the depth mapping differs, and face_projection()
// takes it.

#include <array>
#include <cstdint>
#include <glm/glm.hpp>

#include "backends/common/case_config.h"

namespace omnishadow::cube {

inline constexpr int kFaceCount = 6;
inline constexpr std::array<const char*, kFaceCount> kFaceNames = {"+X", "-X", "+Y", "-Y", "+Z", "-Z"};

inline const std::array<glm::vec3, kFaceCount> kFaceDirections = {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0),
                                                                  glm::vec3(0, 1, 0), glm::vec3(0, -1, 0),
                                                                  glm::vec3(0, 0, 1), glm::vec3(0, 0, -1)};
inline const std::array<glm::vec3, kFaceCount> kFaceUps = {glm::vec3(0, -1, 0), glm::vec3(0, -1, 0),
                                                           glm::vec3(0, 0, 1),  glm::vec3(0, 0, -1),
                                                           glm::vec3(0, -1, 0), glm::vec3(0, -1, 0)};

enum class DepthRange { minus_one_to_one /* GL */, zero_to_one /* Vulkan */ };

// 90-degree vertical field of view, aspect 1: each face covers exactly its quarter of the sphere of
// directions.
glm::mat4 face_projection(float near_plane, float far_plane, DepthRange range);
glm::mat4 face_view(int face, const glm::vec3& light_position);
std::array<glm::mat4, kFaceCount> face_view_projections(const glm::vec3& light_position, float near_plane,
                                                        float far_plane, DepthRange range);

// Storage hardware_depth: texel (s, t) of a face holds the rasteriser's window depth; back to the distance
// from the light along that texel's direction (the axis distance times the texel direction's length). Cleared
// texels (depth 1) read as far, like the other storages.
float projective_depth_to_distance(float window_depth, int s, int t, int size, float near_plane,
                                   float far_plane, DepthRange range);

// What the shadow pass stored at texel (s, t) of a face, as a distance from the light in world units: the one
// conversion for every storage, used by both backends' read-back; shaders/shadow_filters.glsl's
// stored_to_distance() mirrors it per lookup. linear_depth stores distance / far; r32f_distance the distance
// itself (FLT_MAX where nothing was drawn); hardware_depth the projective depth
// (projective_depth_to_distance).
float stored_to_distance(Storage storage, float stored, int s, int t, int size, float near_plane,
                         float far_plane, DepthRange range);

// Cube-map addressing as the samplers do it (spec table 8.19): which face a direction selects and the
// face coordinates (s, t) in [0, 1]. Ties between equal major axes go to x, then y, as in Mesa. Layout
// face_array's lookup (shaders/shadow_filters.glsl, shadow_coord) is the same arithmetic in GLSL: change both
// together.
struct FaceCoord {
  int face;
  float s;
  float t;
};
FaceCoord direction_to_face(const glm::vec3& direction);
// The faces a lookup in `direction` may read on a cube of face_size texels: each whose face, widened by
// `texels` texels across its edges, holds the direction (a face's half-width is 1 in tangent units, size / 2
// texels). The independent answer the view-culling check and its test hold view_culling.h's planes to.
uint8_t faces_within(const glm::vec3& direction, float texels, int face_size);

// The direction through the centre of texel (s, t) of a face of `size`, straight from the same spec table
// (not from the face view matrices above, so that a wrong up vector or face order there cannot hide from a
// check that uses this): the major axis is +-1, the other two components are in (-1, 1).
glm::vec3 texel_direction(int face, int s, int t, int size);
// The same at any point of a face in continuous texel coordinates: texel k spans [k, k + 1), its centre is k
// + 0.5. The truth checks cast through points a sub-pixel step off a texel centre
// (bench/truth/texel_bounds.h).
glm::dvec3 face_point_direction(int face, double s, double t, int size);

// The texel k steps from texel (s, t) of `face` along its s (axis 0) or t (axis 1), continued onto the
// adjacent face as on the unfolded cube where it runs past an edge (|k| <= size): the moments blur's
// addressing, the same integer arithmetic as shaders/cube_texel.glsl, so the moments check replays the
// device's blur texel for texel.
struct FaceTexel {
  int face, s, t;
  bool operator==(const FaceTexel&) const = default;
};
FaceTexel neighbour_texel(int face, int s, int t, int axis, int k, int size);

}  // namespace omnishadow::cube
