#pragma once
// Technique nv_swizzle (NVIDIA's single-pass cube map): the vertex stage writes the light-relative position
// (p - light, near) once, a passthrough geometry shader sends each triangle to six viewports, and viewport
// f's swizzle permutes and negates those four components into face f's clip coordinates. This is the one
// place the swizzles come from: they are read off the face view matrices (cube_faces.h), so face order and up
// vectors have one source of truth.
//
// What a swizzle can express: clip x, y and w of a cube face are each +-1 times one axis of p - light (lookAt
// with axis-aligned vectors, and a 90-degree projection whose scale is exactly 1 in float), so the swizzle
// reproduces them bit for bit. Clip z cannot be a x + b of an axis chosen per face; it is the constant near
// plane instead, so window depth is near / (axis distance): reversed and without a far plane. The near plane
// clips exactly where the projection's does (z <= w is axis >= near). Storages that write their own depth
// (distance / far) are unaffected; r32f_distance tests GREATER (reversed_depth_test, techniques.h) and its
// fragment stage drops what lies past far along the face's axis (FAR_BY_FRAGMENT, shaders/shadow_depth.frag);
// hardware_depth, which stores the projective depth itself, is unsupported.

#include <array>
#include <cstdint>

#include "backends/common/cube_faces.h"

namespace omnishadow::cube {

// In the order of GL_VIEWPORT_SWIZZLE_POSITIVE_X_NV .. NEGATIVE_W_NV (0x9350 + value) and of
// VkViewportCoordinateSwizzleNV (value itself): both extensions number them alike.
enum class SwizzleComponent : uint32_t { pos_x, neg_x, pos_y, neg_y, pos_z, neg_z, pos_w, neg_w };

struct FaceSwizzle {
  SwizzleComponent x, y, z, w;  // the source of clip x, y, z, w
};

std::array<FaceSwizzle, kFaceCount> face_swizzles();

// The clip coordinates viewport `face` produces from the vertex stage's (p - light, near): what the GPU does
// with the swizzle, for the tests and the reference.
glm::vec4 apply_swizzle(const FaceSwizzle& swizzle, const glm::vec4& relative_position);

// --emulate-nv-swizzle (test only): faces 2k and 2k + 1's swizzles as 12 bits each (3 a component, x lowest),
// the SWIZZLES_01 / _23 / _45 defines shaders/shadow_swizzle.geom unpacks, so the emulation applies this
// table itself.
uint32_t packed_swizzle_pair(int k);

}  // namespace omnishadow::cube
