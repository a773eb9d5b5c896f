#pragma once
// Exact visibility from the scene's own triangles, never from a shadow map: the ground truth the GPU shadow
// factor is held against. This first version tests every triangle (fine for the seed scenes, ~100 triangles);
// an acceleration structure belongs here before it is used on the heavy scene.

#include <glm/glm.hpp>

#include <vector>

#include "scenes/scene.h"

namespace omnishadow::reference {

class RayCaster {
 public:
  explicit RayCaster(const scene::Scene& scene);

  // True if any triangle crosses the open segment from `light` to `point`, ignoring hits within
  // `end_epsilon` (world units) of either end, so that the surface holding `point` does not hide itself.
  bool blocked(const glm::vec3& light, const glm::vec3& point, float end_epsilon) const;


 private:
  struct Triangle {
    glm::vec3 a, e1, e2;  // a, b - a, c - a
  };
  std::vector<Triangle> triangles_;
};

}  // namespace omnishadow::reference
