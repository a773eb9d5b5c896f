#pragma once
// A model file run as a scene of its own (`--scene model.glb`): the model as one object, a floor under it,
// and a point light and camera placed from the model's bounds by one rule (docs/guide.md "Your own model"),
// each of which
// `--light` / `--camera` (LoadOptions) replaces.

#include <glm/glm.hpp>
#include <string>

#include "scenes/scene.h"

namespace omnishadow::scene {

// The rule, for a model whose bounds in the file's units are [lo, hi] with +Y up (glTF's convention, and most
// OBJ files'): r = half the bounds' diagonal, c = their centre.
// - scale: world = file * 5 / r, uniformly (no translation, so a model far from the origin stays far from it
// for
//   the rebase remedy). The filters' biases and PCF offsets are the tutorials' world-unit constants (0.05,
//   0.15,
//   +-0.1), tuned for their room of half-width 5; a model in millimetres or kilometres would otherwise be all
//   acne or all peter-panning. In world units the bounding sphere then has radius R = 5 around C = c * 5 / r;
// - floor: a square of side 4R centred under C, 0.01 R below the lowest point (not touching the model, so no
//   surface is coplanar with it);
// - light: at C + H + R (0.5, 0.75, 0.5), H the bounds' half extents: beyond the bounds on +x, +y and +z, the
//   camera's side, so every face of the bounds the camera sees is lit (a box's three: the old rule's light
//   stood over a box's top and left the two sides the camera sees unlit); more than R from C, outside every
//   point of the model;
//   swaying by R/4 along x, position = base + (R/4, 0, 0) sin(0.5 t), the seeds' frequency (0.5 rad/s at 60
//   frames/s), so the shadows move from frame to frame as in the rooms;
// - light planes: near 0.01 R; far 1% beyond the farthest corner of the bounds or the floor from either end
// of
//   the light's path (so the far plane holds all of the scene wherever the light is);
// - camera: 800x600, 45-degree vertical field of view, looking at C from C + 3 R normalize(0.55, 0.45, 1):
// the
//   bounding sphere fills ~87% of the frame's height (R / sin 22.5 deg = 2.61 R), seen from the front, right,
//   above; near 0.01 R, far 3 R beyond its target.
// `--light` (the light's path; its planes are fitted to it as above) and `--camera` (position, and target,
// default C) are given in the file's units and scaled with the model.
inline constexpr double kModelRadius = 5.0;

struct ModelPlacement {  // world units: the file's times `scale`
  double scale = 1.0;
  glm::dvec3 center{0.0};
  double radius = 0.0;
  double floor_y = 0.0;
  double floor_half_size = 0.0;
  LightPlacement light;
  double light_near = 0.0;
  double light_far = 0.0;
  CameraPlacement camera;  // target always set
  double camera_near = 0.0;
  double camera_far = 0.0;
};

// Throws SceneError naming `source` if the bounds are empty, not finite or a single point.
// `lo`, `hi` and the overrides are in the file's units.
ModelPlacement place_model(const glm::dvec3& lo, const glm::dvec3& hi, const LoadOptions& overrides,
                           const std::string& source);

// The model at `path` (.obj, .gltf, .glb) with a floor, light and camera by place_model. Loader errors are
// the loaders' one line naming the file.
Scene load_model_scene(const std::string& path, const LoadOptions& options);

}  // namespace omnishadow::scene
