#include "scenes/tessellate.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace omnishadow::scene {
namespace {

// The grid point (u, v, w) / n of triangle (a, b, c), u + v + w = n.
glm::vec3 blend(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, int u, int v, int w, int n) {
  const glm::dvec3 sum = glm::dvec3(a) * double(u) + glm::dvec3(b) * double(v) + glm::dvec3(c) * double(w);
  return glm::vec3(sum / double(n));
}

Vertex grid_vertex(const Vertex* t, int i, int j, int n) {
  const int u = n - i - j;
  Vertex out;
  out.position = blend(t[0].position, t[1].position, t[2].position, u, i, j, n);
  out.normal = glm::normalize(blend(t[0].normal, t[1].normal, t[2].normal, u, i, j, n));
  out.color = blend(t[0].color, t[1].color, t[2].color, u, i, j, n);
  return out;
}

}  // namespace

void tessellate(Scene& scene, int n) {
  if (n < 1) throw std::invalid_argument("--tessellate: a subdivision of at least 1");
  if (n == 1) return;
  const uint64_t triangles = uint64_t(scene.vertices.size() / 3) * uint64_t(n) * uint64_t(n);
  if (triangles > kMaxTessellatedTriangles)
    throw std::invalid_argument("--tessellate " + std::to_string(n) + ": scene " + scene.name +
                                " would have " + std::to_string(triangles) + " triangles, more than " +
                                std::to_string(kMaxTessellatedTriangles));
  std::vector<Vertex> out;
  out.reserve(scene.vertices.size() * size_t(n) * size_t(n));
  for (Object& o : scene.objects) {
    const uint32_t first = static_cast<uint32_t>(out.size());
    for (uint32_t v = o.first_vertex; v + 3 <= o.first_vertex + o.vertex_count; v += 3) {
      const Vertex* t = &scene.vertices[v];
      // Point (i, j): i steps towards t[1], j towards t[2]. "Up" triangles keep (a, b, c)'s winding, and so
      // do "down" ones: (p(i+1, j), p(i+1, j+1), p(i, j+1)).
      for (int i = 0; i < n; ++i)
        for (int j = 0; i + j < n; ++j) {
          out.push_back(grid_vertex(t, i, j, n));
          out.push_back(grid_vertex(t, i + 1, j, n));
          out.push_back(grid_vertex(t, i, j + 1, n));
          if (i + j + 1 < n) {
            out.push_back(grid_vertex(t, i + 1, j, n));
            out.push_back(grid_vertex(t, i + 1, j + 1, n));
            out.push_back(grid_vertex(t, i, j + 1, n));
          }
        }
    }
    o.first_vertex = first;
    o.vertex_count = static_cast<uint32_t>(out.size()) - first;
  }
  scene.vertices = std::move(out);
}

}  // namespace omnishadow::scene
