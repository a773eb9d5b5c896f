#pragma once
// The lights of a scene file (scenes/README.md): "light", the one point light of the tutorials, or "lights",
// any number of point lights (each its own shadow map) and up to four spot or directional lights (one 2D map
// each). Internal to scenes/.

#include "scenes/scene.h"
#include "scenes/scene_json.h"

namespace omnishadow::scene::detail {

// Fills scene.point_lights and scene.map_lights from the file's root object; positions are stored relative
// to scene.origin. Throws SceneError naming the field.
void parse_lights(const Node& root, Scene& scene);
// A "path" object's fields over `path` (amplitude, frequency, seconds_per_frame, phase): a light's, or a
// moving object's (base 0).
LightPath parse_path_fields(const Node& p, LightPath path);

}  // namespace omnishadow::scene::detail
