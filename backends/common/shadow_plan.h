#pragma once
// What the shadow pass must draw, decided once on the CPU for both backends: per face, the objects whose
// bounds touch that face's frustum (six_pass; a face with none is cleared only), and per object the faces it
// touches (vs_layer instances). Also the far plane fitted to the scene around the light.
//
// The frustum test is conservative: an object is dropped from a face only when its box lies wholly beyond one
// of the face's planes (by a margin), i.e. where clipping would discard every one of its triangles anyway, so
// the images are bit-identical with and without culling.

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "scenes/scene.h"

namespace omnishadow::cube {

inline constexpr uint8_t kAllFaces = 0x3f;

// Bit f set when the box [lo, hi] may reach face f's frustum: the 90-degree pyramid along the face axis from
// the light, between the axis distances near and far (the projection's planes).
uint8_t box_face_mask(const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& light, float near_plane,
                      float far_plane);

// The faces of a light at `light` (its near and far) whose content a moving caster changed between frames
// `then` and `now`: each moving object whose offset differs between them, where its box at either frame may
// reach the face (what the face held of it, and what it must hold now). The dirty rule of cached and budgeted
// faces; a static scene has none.
uint8_t moved_caster_faces(const scene::Scene& scene, const glm::vec3& light, float near_plane,
                           float far_plane, int then, int now);

struct ShadowDrawPlan {
  std::array<std::vector<uint32_t>, 6> face_objects;  // indices into Scene::objects, per face
  std::vector<uint8_t> object_faces;                  // per object, bit f = face f
  std::vector<uint32_t> reaching;                     // objects whose mask is not empty (single-pass draws)
  int empty_faces = 0;                                // faces with nothing to draw
};
// cull = false: every object in every face (the unoptimised plan).
ShadowDrawPlan plan_shadow_draws(const scene::Scene& scene, const glm::vec3& light, float near_plane,
                                 float far_plane, bool cull);

// Only `faces` drawn (view culling): every other face's list emptied (cleared only), each object's mask cut.
void keep_faces(ShadowDrawPlan& plan, uint8_t faces);

// The far plane the shadow pass needs: the farthest bounds corner from the light (a bound on the farthest
// vertex), slightly enlarged, never beyond the scene's own far, never below near * 2.
float fitted_far(const scene::Scene& scene, const glm::vec3& light, float near_plane, float scene_far);

}  // namespace omnishadow::cube
