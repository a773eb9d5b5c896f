#include "backends/reference/ray_caster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "backends/reference/wide_bvh.h"

namespace omnishadow::reference {
namespace {

constexpr uint32_t kLeafSize = 4;
constexpr int kMaxDepth = 60;  // walk()'s stack (256) gains at most three entries a level
constexpr double kMissed = std::numeric_limits<double>::infinity();

float surface_area(const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 d = hi - lo;
  return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
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
  wide_ = collapse_to_wide(nodes_);
  for (auto* scratch : {&centroids_, &tri_min_, &tri_max_}) *scratch = {};
  nodes_ = {};
}

void RayCaster::build(uint32_t index, uint32_t first, uint32_t count, int depth) {
  BinaryNode node{glm::vec3(INFINITY), 0, glm::vec3(-INFINITY), 0};
  glm::vec3 cmin(INFINITY), cmax(-INFINITY);
  for (uint32_t i = first; i < first + count; ++i) {
    node.min = glm::min(node.min, tri_min_[order_[i]]);
    node.max = glm::max(node.max, tri_max_[order_[i]]);
    cmin = glm::min(cmin, centroids_[order_[i]]);
    cmax = glm::max(cmax, centroids_[order_[i]]);
  }
  if (count <= kLeafSize || depth >= kMaxDepth) {
    node.first = first;
    node.count = count;
    nodes_[index] = node;
    return;
  }
  const uint32_t half = split(first, count, cmin, cmax);
  const uint32_t left = static_cast<uint32_t>(nodes_.size());  // children as a pair: right = left + 1
  nodes_.emplace_back();
  nodes_.emplace_back();
  node.first = left;
  nodes_[index] = node;
  build(left, first, half, depth + 1);
  build(left + 1, first + half, count - half, depth + 1);
}

// Binned surface-area heuristic (Wald 2007): the triangles' centroids in kBins slabs along each axis, and the
// boundary that minimises area(left) * count(left) + area(right) * count(right), the expected cost of a
// random ray meeting the parent. Deterministic (no randomness, ties go to the first axis and bin); returns
// the left part's size, the part placed first in order_.
uint32_t RayCaster::split(uint32_t first, uint32_t count, const glm::vec3& cmin, const glm::vec3& cmax) {
  constexpr int kBins = 16;
  struct Bin {
    glm::vec3 lo{INFINITY}, hi{-INFINITY};
    uint32_t n = 0;
  };
  auto bin_of = [&](uint32_t t, int axis) {
    // NaN (a centroid that overflowed, coordinates near float's limit) goes to bin 0: no undefined
    // conversion.
    const float at = (centroids_[t][axis] - cmin[axis]) * (float(kBins) / (cmax[axis] - cmin[axis]));
    return at >= float(kBins - 1) ? kBins - 1 : (at > 0.0f ? static_cast<int>(at) : 0);
  };
  float best_cost = INFINITY;
  int best_axis = -1, best_bin = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (!(cmax[axis] > cmin[axis])) continue;
    std::array<Bin, kBins> bins;
    for (uint32_t i = first; i < first + count; ++i) {
      Bin& b = bins[size_t(bin_of(order_[i], axis))];
      b.lo = glm::min(b.lo, tri_min_[order_[i]]);
      b.hi = glm::max(b.hi, tri_max_[order_[i]]);
      ++b.n;
    }
    std::array<float, kBins> right_cost{};  // right_cost[b]: bins b.. as one side
    Bin side;
    for (int b = kBins - 1; b > 0; --b) {
      side = {glm::min(side.lo, bins[size_t(b)].lo), glm::max(side.hi, bins[size_t(b)].hi),
              side.n + bins[size_t(b)].n};
      right_cost[size_t(b)] = side.n ? surface_area(side.lo, side.hi) * float(side.n) : 0.0f;
    }
    side = Bin{};
    for (int b = 0; b + 1 < kBins; ++b) {
      side = {glm::min(side.lo, bins[size_t(b)].lo), glm::max(side.hi, bins[size_t(b)].hi),
              side.n + bins[size_t(b)].n};
      const float cost =
          (side.n ? surface_area(side.lo, side.hi) * float(side.n) : 0.0f) + right_cost[size_t(b) + 1];
      if (side.n > 0 && side.n < count && cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_bin = b;
      }
    }
  }
  if (best_axis < 0) return median_split(first, count, cmin, cmax);
  auto middle = std::partition(order_.begin() + first, order_.begin() + first + count,
                               [&](uint32_t t) { return bin_of(t, best_axis) <= best_bin; });
  return static_cast<uint32_t>(middle - (order_.begin() + first));
}

// Where every centroid coincides (no boundary separates them): halves by index along the widest axis.
uint32_t RayCaster::median_split(uint32_t first, uint32_t count, const glm::vec3& cmin,
                                 const glm::vec3& cmax) {
  const glm::vec3 extent = cmax - cmin;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const uint32_t half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](uint32_t a, uint32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
  return half;
}

template <typename OnTriangle>
void RayCaster::traverse(const glm::dvec3& origin, const glm::dvec3& dir, double max_distance,
                         OnTriangle on) const {
  if (wide_.empty()) return;
  const glm::vec3 origin_f(origin);
  bool in_float = glm::dvec3(origin_f) == origin;
  for (int k = 0; k < 3; ++k) in_float = in_float && std::fabs(dir[k]) >= kFloatParallel;
  const glm::dvec3 inv(1.0 / dir.x, 1.0 / dir.y, 1.0 / dir.z);
  if (in_float) {
    const glm::vec3 inv_f(inv);
    walk(
        max_distance,
        [&](const WideNode& n, double limit, double entry[4]) {
          // Out of float's range the conversion would be undefined: no float box lies beyond infinity.
          const float reach =
              limit < double(std::numeric_limits<float>::max()) ? static_cast<float>(limit) : INFINITY;
          enter_wide(n, origin_f, inv_f, reach, entry);
        },
        on);
  } else {
    walk(
        max_distance,
        [&](const WideNode& n, double limit, double entry[4]) { enter_wide(n, origin, inv, limit, entry); },
        on);
  }
}

// Each box is tested once, with its siblings, when its parent is visited; the entry distance travels with it
// on the stack, so that closest() skips a node or leaf that a nearer hit has since put beyond reach.
template <typename BoxTest, typename OnTriangle>
void RayCaster::walk(double max_distance, BoxTest enter, OnTriangle on) const {
  struct Entry {
    uint32_t index;  // a wide node, or (count > 0) a leaf's first triangle in order_
    uint32_t count;
    double entry;
  };
  Entry stack[256];  // three more entries a level at most, 60 levels
  int top = 0;
  stack[top++] = {0, 0, 0.0};
  while (top > 0) {
    const Entry e = stack[--top];
    if (beyond(e.entry, max_distance)) continue;
    if (e.count > 0) {
      for (uint32_t i = e.index; i < e.index + e.count; ++i) {
        max_distance = on(order_[i], max_distance);
        if (max_distance < 0) return;
      }
      continue;
    }
    const WideNode& node = wide_[e.index];
    double entry[4];
    enter(node, max_distance, entry);
    // The lanes met, farthest first onto the stack, so that the nearest is visited next.
    const int base = top;
    for (int lane = 0; lane < 4; ++lane) {
      if (entry[lane] == kMissed) continue;
      Entry in{node.child[lane], node.count[lane], entry[lane]};
      int at = top++;
      for (; at > base && stack[at - 1].entry < in.entry; --at) stack[at] = stack[at - 1];
      stack[at] = in;
    }
  }
}

bool RayCaster::blocked(const glm::vec3& from, const glm::vec3& to, float end_epsilon,
                        uint32_t* last_blocker) const {
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
  return closest_kept(origin_f, direction, max_distance, {});
}

Hit RayCaster::closest_kept(const glm::vec3& origin_f, const glm::vec3& direction, double max_distance,
                            const std::function<bool(uint32_t triangle)>& keep) const {
  const glm::dvec3 origin(origin_f), dir(direction);
  Hit best;
  traverse(origin, dir, max_distance, [&](uint32_t t, double limit) {
    if (keep && !keep(t)) return limit;
    const Triangle& tri = triangles_[t];
    double u = 0, v = 0;
    double d = intersect(origin, dir, tri.a, tri.e1, tri.e2, &u, &v);
    // Of hits at one distance, the lowest triangle index: the answer does not hang on the visiting order.
    if (d > 0.0 && (d < limit || (best.hit && d == limit && t < best.triangle))) {
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

glm::vec3 RayCaster::color_at(const Hit& h) const {
  return vertices_[3 * static_cast<size_t>(h.triangle)]->color;
}

}  // namespace omnishadow::reference
