#pragma once
// Spot and directional lights need no cube: one 2D map each. This is where their view-projections are built,
// for both APIs (only the clip depth range differs), so backends and the reference agree on what each map
// covers.

#include <glm/glm.hpp>

#include "backends/common/cube_faces.h"
#include "scenes/scene.h"

namespace omnishadow::gpu {

// Spot: perspective over the cone (cone_degrees square), from the light's position at `frame`, near/far as
// given. Directional: orthographic along the light's direction, fitted to the scene's bounds (every object's
// box inside the map, depth range included, with a 1% margin), as the directional notes fits its ortho box by
// hand.
glm::mat4 map_view_projection(const scene::Scene& scene, const scene::MapLight& light, int frame,
                              cube::DepthRange range);

// The up vector lookAt needs: any axis not parallel to the direction.
glm::vec3 map_up(const glm::vec3& direction);

}  // namespace omnishadow::gpu
