#pragma once
// Subdivides every triangle of a scene into n^2 (a layout that warps vertices, dual_paraboloid,
// draws straight edges where the exact map curves, so its error depends on how finely casters are
// tessellated; the
// `--tessellate` axis measures that). The surfaces are the same: each sub-triangle lies in its triangle's
// plane, with its winding, its object and its interpolated normal and colour; the truths cast against the
// subdivided triangles.
//
// Points on an edge are computed from the edge's two ends alone, in double, by a sum that does not depend on
// which triangle computes it (a*u + b*v with u + v = n, commutative; the third term is an exact zero), so
// triangles that shared an edge share its new vertices bit for bit: no cracks.

#include "scenes/scene.h"

namespace omnishadow::scene {

// At most this many triangles after subdivision (36 bytes a vertex: 1.8 GB of vertices); more is refused, one
// line naming the scene, rather than left to fail inside a driver's allocation.
inline constexpr uint64_t kMaxTessellatedTriangles = uint64_t(1) << 24;

// n = 1 leaves the scene as it is; n >= 2 multiplies its triangle count by n^2. Object ranges follow. Throws
// std::invalid_argument for n < 1 or beyond kMaxTessellatedTriangles.
void tessellate(Scene& scene, int n);

}  // namespace omnishadow::scene
