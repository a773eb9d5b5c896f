#pragma once
// Culling to the camera's view (--optimize view): which of a light's cube faces the lit frame can read. The
// lighting pass shades a pixel with a light only within its range (shaders/lighting.frag masks the lookup
// beyond far), and every pixel it shades lies in the camera's frustum, so a light whose range sphere misses
// the frustum needs no map, and a face no lookup of a visible point in range can reach needs no pass.
//
// Conservative by construction, so the lit frame is bit-identical with and without it: the visible part of
// the range lies in the frustum cut to the sphere's depth span; every sample a lookup takes lies within the
// filter's world reach of its point (a PCF kernel's offsets, the normal-offset remedy's shift); a sample
// reads the face its direction picks and, through bilinear taps, seamless filtering and the moments blur,
// texels up to the filter's texel reach across that face's edges. A face is dropped only when a separating
// plane (one of its direction cone's four sides widened by the texel reach, or one of the cut frustum's six)
// shows that no such sample reaches it.

#include <cstdint>
#include <glm/glm.hpp>

#include "backends/common/case_config.h"
#include "scenes/scene.h"

namespace omnishadow::cube {

// The camera's frustum: eye, unit axes, tangents of the half angles, near and far (world units).
struct ViewVolume {
  glm::vec3 eye{0.0f}, forward{0.0f, 0.0f, -1.0f}, right{1.0f, 0.0f, 0.0f}, up{0.0f, 1.0f, 0.0f};
  float tan_half_x = 1.0f, tan_half_y = 1.0f;
  float near_plane = 0.1f, far_plane = 100.0f;
};
// The frustum of make_frame_uniforms' camera for a width x height frame (fov_y vertical, aspect
// width/height).
ViewVolume camera_view(const scene::Camera& camera, int width, int height);

// How far from its point a lookup's samples may go: `world` units in any direction, and `texels` of the face
// size across a face's edges. bounded = false: no bound (PCSS's penumbra grows without one), so every face of
// a light in view is kept.
struct LookupReach {
  float world = 0.0f;
  float texels = 0.0f;
  bool bounded = true;
};

// Bit f set when a lookup of a visible point within `range` of `light` may read face f of a face_size cube; 0
// when no visible point lies within range (the light needs no map). per_face = false: only that whole-light
// answer (kAllFaces or 0), for layouts whose layers are not cube faces.
uint8_t view_face_mask(const ViewVolume& view, const glm::vec3& light, float range, const LookupReach& reach,
                       int face_size, bool per_face);

}  // namespace omnishadow::cube

namespace omnishadow::gpu {

// The filter's reach for a light of `range` seen from a camera `camera_distance` from it (the disk kernel
// widens with the view distance).
cube::LookupReach lookup_reach(const CaseConfig& c, float range, float camera_distance, int face_size);

// Whether the case's technique and layout can leave single faces out (the others cull whole lights only):
// per-face passes, per-object face masks and the geometry shaders' per-face emission, over cube faces.
bool culls_faces_to_view(const CaseConfig& c);

// The faces of the scene's focused light (at `frame`, rendered with far plane `range` into face_size tiles)
// that the case's frame renders: kAllFaces without view culling.
uint8_t view_faces(const scene::Scene& scene, const CaseConfig& c, int frame, float range, int face_size);

}  // namespace omnishadow::gpu
