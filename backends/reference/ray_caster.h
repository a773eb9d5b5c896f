#pragma once
// Exact visibility from the scene's own triangles, never from a shadow map: the ground truth every GPU shadow
// factor is held against. Triangles are tested in double; a four-wide SAH bounding-volume hierarchy with
// float box tests (wide_bvh.h: conservative, it never culls a triangle the double ray meets, so every answer
// is that of testing every triangle) keeps 800x600 pixels x 64 light samples on the heavy scene (110k
// triangles) to a few seconds.

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "backends/reference/wide_bvh.h"
#include "scenes/scene.h"

namespace omnishadow::reference {

struct Hit {
  bool hit = false;
  double distance = 0.0;  // along the unit direction
  uint32_t triangle = 0;
  double u = 0.0, v = 0.0;  // barycentrics of vertices 1 and 2
};

class RayCaster {
 public:
  explicit RayCaster(const scene::Scene& scene);

  // True if any triangle crosses the segment from `from` to `to`, ignoring hits within `end_epsilon` (world
  // units) of either end, so that the surface holding an end point does not hide it from itself. Both sides
  // of every triangle block: shadow casters are not culled.
  // `last_blocker` (optional, per thread): the triangle that blocked this caller's previous ray, tried first
  // (neighbouring rays of one light are mostly blocked by the same triangle) and updated when another blocks.
  // The answer is the same with or without it: any triangle crossing the segment answers it, found first or
  // not.
  bool blocked(const glm::vec3& from, const glm::vec3& to, float end_epsilon,
               uint32_t* last_blocker = nullptr) const;
  static constexpr uint32_t kNoBlocker = 0xffffffffu;
  // The nearest hit along `direction` (unit) within (0, max_distance); of hits at one distance (an edge or
  // vertex that triangles share), the lowest triangle index, whatever order the hierarchy visits them in.
  Hit closest(const glm::vec3& origin, const glm::vec3& direction, double max_distance) const;
  // The same among the triangles `keep` accepts; the others let the ray through (a culled face). One search,
  // not a walk from hit to hit: a kept face at the distance of a dropped one (the two faces of a box's edge)
  // is still found.
  Hit closest_kept(const glm::vec3& origin, const glm::vec3& direction, double max_distance,
                   const std::function<bool(uint32_t triangle)>& keep) const;

  // Shading data of a hit: the interpolated vertex normal (unit, the scene's lit side) and the albedo.
  glm::vec3 normal_at(const Hit& hit) const;
  glm::vec3 color_at(const Hit& hit) const;
  size_t triangle_count() const { return triangles_.size(); }

 private:
  struct Triangle {
    glm::dvec3 a, e1, e2;  // a, b - a, c - a (double: the answer must not hinge on float rounding at edges)
  };
  // Calls hit(triangle index, distance) for triangles whose bounds the ray meets within `max_distance`,
  // nearest nodes first; `hit` returns the new max distance (or < 0 to stop). Boxes are tested in float where
  // that is provably conservative (ray_caster.cpp), in double otherwise: culling never drops a triangle the
  // double ray meets.
  template <typename OnTriangle>
  void traverse(const glm::dvec3& origin, const glm::dvec3& direction, double max_distance,
                OnTriangle on) const;
  template <typename BoxTest, typename OnTriangle>
  void walk(double max_distance, BoxTest enter, OnTriangle on) const;
  void build(uint32_t index, uint32_t first, uint32_t count, int depth);
  uint32_t split(uint32_t first, uint32_t count, const glm::vec3& cmin, const glm::vec3& cmax);
  uint32_t median_split(uint32_t first, uint32_t count, const glm::vec3& cmin, const glm::vec3& cmax);

  std::vector<Triangle> triangles_;
  std::vector<const scene::Vertex*>
      vertices_;  // three per triangle, into the scene (kept alive by the caller)
  std::vector<uint32_t> order_;
  std::vector<BinaryNode> nodes_;  // the binary build, collapsed into wide_ and freed
  std::vector<WideNode> wide_;
  std::vector<glm::vec3> centroids_, tri_min_, tri_max_;
};

// Intersects a unit-direction ray with one triangle (Moller-Trumbore); returns the distance or -1.
double intersect(const glm::dvec3& origin, const glm::dvec3& dir, const glm::dvec3& a, const glm::dvec3& e1,
                 const glm::dvec3& e2, double* u, double* v);

}  // namespace omnishadow::reference
