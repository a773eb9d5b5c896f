// Moving casters and camera (scenes/README.md, "path" on an object or the camera): the scene at a frame.

#include <algorithm>

#include "scenes/scene.h"

namespace omnishadow::scene {

bool Scene::has_moving_objects() const {
  return std::any_of(objects.begin(), objects.end(), [](const Object& o) { return o.moves(); });
}

Camera Camera::at(int frame) const {
  if (!moves()) return *this;
  Camera c = *this;
  const glm::vec3 offset = path.at(frame);
  c.position += offset;
  c.target += offset;
  c.path = LightPath{};
  return c;
}

void Scene::pose(int frame) {
  if (frame == posed_frame || !has_moving_objects()) return;
  if (rest_positions.empty()) {  // still at rest: what the file put where
    rest_positions.reserve(vertices.size());
    for (const Vertex& v : vertices) rest_positions.push_back(v.position);
  }
  for (Object& o : objects) {
    if (!o.moves()) continue;
    const glm::vec3 offset = o.offset_at(frame);
    for (uint32_t i = o.first_vertex; i < o.first_vertex + o.vertex_count; ++i)
      vertices[i].position = rest_positions[i] + offset;
    o.bounds_min = o.rest_bounds_min + offset;
    o.bounds_max = o.rest_bounds_max + offset;
  }
  posed_frame = frame;
}

void Scene::put_at_rest() {
  if (posed_frame < 0) return;
  for (Object& o : objects) {
    if (!o.moves()) continue;
    for (uint32_t i = o.first_vertex; i < o.first_vertex + o.vertex_count; ++i)
      vertices[i].position = rest_positions[i];
    o.bounds_min = o.rest_bounds_min;
    o.bounds_max = o.rest_bounds_max;
  }
  posed_frame = -1;
}

}  // namespace omnishadow::scene
