#include "backends/reference/ray_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace omnishadow::reference {
namespace {

constexpr uint32_t kLeafSize = 4;

// Slab test; returns the entry distance or +inf when the box is missed within [0, max_distance].
double enter_box(const glm::vec3& lo, const glm::vec3& hi, const glm::dvec3& origin, const glm::dvec3& inv_dir,
                 double max_distance) {
  double t0 = 0.0, t1 = max_distance;
  for (int k = 0; k < 3; ++k) {
    double a = (lo[k] - origin[k]) * inv_dir[k];
    double b = (hi[k] - origin[k]) * inv_dir[k];
    if (a > b) std::swap(a, b);
    // NaN (0 * inf for a ray in the slab's plane) must not reject: keep the current bounds.
    if (a > t0) t0 = a;
    if (b < t1) t1 = b;
    if (t0 > t1) return std::numeric_limits<double>::infinity();
  }
  return t0;
}

}  // namespace

double intersect(const glm::dvec3& origin, const glm::dvec3& dir, const glm::dvec3& a, const glm::dvec3& e1,
                 const glm::dvec3& e2, double* u_out, double* v_out) {
  const glm::dvec3 p = glm::cross(dir, e2);
  const double det = glm::dot(e1, p);
  if (std::fabs(det) < 1e-18) return -1.0;  // parallel or degenerate
  const double inv = 1.0 / det;
  const glm::dvec3 s = origin - a;
  const double u = glm::dot(s, p) * inv;
  if (u < 0.0 || u > 1.0) return -1.0;
  const glm::dvec3 q = glm::cross(s, e1);
  const double v = glm::dot(dir, q) * inv;
  if (v < 0.0 || u + v > 1.0) return -1.0;
  if (u_out) *u_out = u;
  if (v_out) *v_out = v;
  return glm::dot(e2, q) * inv;
}

RayCaster::RayCaster(const scene::Scene& scene) {
  const size_t n = scene.vertices.size() / 3;
  triangles_.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3 a(scene.vertices[3 * i].position), b(scene.vertices[3 * i + 1].position),
        c(scene.vertices[3 * i + 2].position);
    triangles_.push_back({a, b - a, c - a});
    for (int k = 0; k < 3; ++k) vertices_.push_back(&scene.vertices[3 * i + static_cast<size_t>(k)]);
    glm::vec3 lo = glm::min(glm::vec3(a), glm::min(glm::vec3(b), glm::vec3(c)));
    glm::vec3 hi = glm::max(glm::vec3(a), glm::max(glm::vec3(b), glm::vec3(c)));
    tri_min_.push_back(lo);
    tri_max_.push_back(hi);
    centroids_.push_back(0.5f * (lo + hi));
    order_.push_back(static_cast<uint32_t>(i));
  }
  nodes_.reserve(4 * n / kLeafSize + 2);
  if (n > 0) {
    nodes_.emplace_back();
    build(0, 0, static_cast<uint32_t>(n), 0);
  }
  centroids_.clear();
  centroids_.shrink_to_fit();
}

void RayCaster::build(uint32_t index, uint32_t first, uint32_t count, int depth) {
  Node node{glm::vec3(INFINITY), glm::vec3(-INFINITY), first, count};
  glm::vec3 cmin(INFINITY), cmax(-INFINITY);
  for (uint32_t i = first; i < first + count; ++i) {
    node.min = glm::min(node.min, tri_min_[order_[i]]);
    node.max = glm::max(node.max, tri_max_[order_[i]]);
    cmin = glm::min(cmin, centroids_[order_[i]]);
    cmax = glm::max(cmax, centroids_[order_[i]]);
  }
  if (count <= kLeafSize || depth > 60) {
    nodes_[index] = node;
    return;
  }
  // Median split on the widest axis of the centroids: simple, deterministic, good enough for static scenes.
  glm::vec3 extent = cmax - cmin;
  int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  uint32_t half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](uint32_t a, uint32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
  const uint32_t left = static_cast<uint32_t>(nodes_.size());  // children as a pair: right = left + 1
  nodes_.emplace_back();
  nodes_.emplace_back();
  node.first = left;
  node.count = 0;
  nodes_[index] = node;
  build(left, first, half, depth + 1);
  build(left + 1, first + half, count - half, depth + 1);
}

template <typename OnTriangle>
void RayCaster::traverse(const glm::dvec3& origin, const glm::dvec3& dir, double max_distance, OnTriangle on) const {
  if (nodes_.empty()) return;
  const glm::dvec3 inv(1.0 / dir.x, 1.0 / dir.y, 1.0 / dir.z);
  uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (enter_box(node.min, node.max, origin, inv, max_distance) == std::numeric_limits<double>::infinity()) continue;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        max_distance = on(order_[i], max_distance);
        if (max_distance < 0) return;
      }
    } else {
      // Visit the nearer child first so that closest() shrinks max_distance early.
      const Node& l = nodes_[node.first];
      const Node& r = nodes_[node.first + 1];
      double dl = enter_box(l.min, l.max, origin, inv, max_distance);
      double dr = enter_box(r.min, r.max, origin, inv, max_distance);
      if (dl <= dr) {
        stack[top++] = node.first + 1;
        stack[top++] = node.first;
      } else {
        stack[top++] = node.first;
        stack[top++] = node.first + 1;
      }
    }
  }
}

bool RayCaster::blocked(const glm::vec3& from, const glm::vec3& to, float end_epsilon, uint32_t* last_blocker) const {
  const glm::dvec3 origin(from);
  const glm::dvec3 segment = glm::dvec3(to) - origin;
  const double length = glm::length(segment);
  if (length <= 2.0 * end_epsilon) return false;
  const glm::dvec3 dir = segment / length;
  const double max_distance = length - end_epsilon;
  // The same test as in the traversal below, on the previous blocker first.
  auto blocks = [&](uint32_t t, double limit) {
    const Triangle& tri = triangles_[t];
    const double d = intersect(origin, dir, tri.a, tri.e1, tri.e2, nullptr, nullptr);
    return d > end_epsilon && d < limit;
  };
  if (last_blocker && *last_blocker < triangles_.size() && blocks(*last_blocker, max_distance)) return true;
  bool found = false;
  traverse(origin, dir, max_distance, [&](uint32_t t, double limit) {
    if (!blocks(t, limit)) return limit;
    found = true;
    if (last_blocker) *last_blocker = t;
    return -1.0;  // any hit answers the question
  });
  return found;
}

Hit RayCaster::closest(const glm::vec3& origin_f, const glm::vec3& direction, double max_distance) const {
  const glm::dvec3 origin(origin_f), dir(direction);
  Hit best;
  traverse(origin, dir, max_distance, [&](uint32_t t, double limit) {
    const Triangle& tri = triangles_[t];
    double u = 0, v = 0;
    double d = intersect(origin, dir, tri.a, tri.e1, tri.e2, &u, &v);
    if (d > 0.0 && d < limit) {
      best = {true, d, t, u, v};
      return d;
    }
    return limit;
  });
  return best;
}

glm::vec3 RayCaster::normal_at(const Hit& h) const {
  const scene::Vertex* const* v = &vertices_[3 * static_cast<size_t>(h.triangle)];
  glm::vec3 n = static_cast<float>(1.0 - h.u - h.v) * v[0]->normal + static_cast<float>(h.u) * v[1]->normal +
                static_cast<float>(h.v) * v[2]->normal;
  float len = glm::length(n);
  return len > 0.0f ? n / len : v[0]->normal;
}

glm::vec3 RayCaster::color_at(const Hit& h) const { return vertices_[3 * static_cast<size_t>(h.triangle)]->color; }

}  // namespace omnishadow::reference
