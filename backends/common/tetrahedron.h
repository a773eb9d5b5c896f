#pragma once
// Tetrahedral layout conventions (layout tetrahedral; bgfx's point-light example renders the same
// four frusta): the one source of truth for its faces, used by the frame uniforms (shadow pass), the truths
// and the tests; shaders/shadow_filters.glsl's LAYOUT_TETRAHEDRAL lookup computes the same bases from the
// same rule (change both together).
//
// Four faces around the light, along the directions of a regular tetrahedron's vertices, (1,1,1), (1,-1,-1),
// (-1,1,-1), (-1,-1,1) over sqrt 3. A direction belongs to the face whose axis it is closest to (ties to the
// lower face); that cell is a spherical triangle whose corners are the other axes' antipodes, 70.53 degrees
// off the axis. Each face is a perspective camera along its axis (a GL camera, lookAt's right = axis x up)
// with `up` towards the corner opposite the next face (-axis[(f + 1) % 4]); on the plane one unit along the
// axis the cell is the triangle (0, 2 sqrt 2), (+-sqrt 6, -sqrt 2), and the frustum is its bounding box: x in
// [-sqrt 6, sqrt 6], y in
// [-sqrt 2, 2 sqrt 2]. As the cube faces: clip y = -1 on the first row in memory, s grows with x and t with
// y.

#include <array>
#include <glm/glm.hpp>

#include "backends/common/cube_faces.h"

namespace omnishadow::tetra {

inline constexpr int kFaceCount = 4;
inline constexpr std::array<const char*, kFaceCount> kFaceNames = {"T0", "T1", "T2", "T3"};

struct Face {
  glm::dvec3 axis, right, up;  // unit, orthogonal: window x along right, window y along up
};
const std::array<Face, kFaceCount>& faces();

// The frustum's bounding box on the plane one unit along the axis.
inline constexpr double kLeft = -2.449489742783178, kRight = 2.449489742783178;    // -+sqrt 6
inline constexpr double kBottom = -1.4142135623730951, kTop = 2.8284271247461903;  // -sqrt 2, 2 sqrt 2

// Layer edge at the memory of a cube of `cube_size`: 4 S^2 = 6 N^2.
int layer_size_for_cube(int cube_size);

// Face f's view-projection from the light (glm::lookAt along the axis, glm::frustum of the box above).
glm::mat4 face_view_projection(int face, const glm::vec3& light_position, float near_plane, float far_plane,
                               cube::DepthRange range);

// The face a direction selects: the axis with the largest dot product, ties to the lower face.
int direction_to_face(const glm::dvec3& direction);
// The direction through a point of a face of `size` in continuous texel coordinates (texel k's centre at k +
// 0.5), with axis component 1 (so its length is distance over axis distance, as the cube's
// face_point_direction).
glm::dvec3 face_point_direction(int face, double s, double t, int size);

}  // namespace omnishadow::tetra
