#include "backends/reference/ray_caster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace omnishadow::reference {
namespace {

constexpr uint32_t kLeafSize = 4;
constexpr int kMaxDepth = 60;  // the traversal stack (128) holds at most depth + 1 entries
constexpr double kMissed = std::numeric_limits<double>::infinity();

// Node boxes are tested in float (enter_box_float), about twice as fast as double, and conservatively: the test never
// misses a box the double ray meets within [0, max_distance]. The origin converts exactly (traverse() checks it is
// a float), and each direction component is at least kFloatParallel, so |inv| <= 1e12 and no slab distance is NaN.
// Each slab distance then carries at most three roundings (1/dir to float, lo - o, the product): relative error
// (1 + u)^3 with u = 2^-24, except where lo - o is subnormal, which the subtraction gives exactly and the product
// rounds by at most 2^-149 absolute. The entry t0 is thus at most (1 + u)^3 high and the exit t1 (or
// float(max_distance)) at most (1 + u)^3 low, so a box the exact ray meets (t0 <= t1) has t0_f <= t1_f * (1 + u)^3 /
// (1 - u)^3, about 1 + 6u; the test allows t1_f * kWiden + kSlack, whose product rounds by one more u: kWiden =
// 1 + 2^-20 = 1 + 16u leaves a margin of more than 8u, and kSlack (1e-30) covers the subnormal roundings. The same
// allowance covers the triangle test's own rounding (a vertex on a box's face whose computed distance is a few double
// ulps short of the exact one) and the double test's (the same three roundings with u = 2^-53).
constexpr double kFloatParallel = 1e-12;
constexpr float kWiden = 1.0f + 0x1p-20f;
constexpr float kSlack = 1e-30f;
inline bool beyond(double entry, double limit) { return entry > limit * double(kWiden) + double(kSlack); }

// The slab test in double, for rays the float test cannot take (almost axis-parallel, or a non-float origin);
// returns the entry distance or +inf when the box is missed within [0, max_distance].
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
  }
  return beyond(t0, t1) ? kMissed : t0;
}

[[gnu::always_inline]] inline float enter_box_float(const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& origin, const glm::vec3& inv_dir,
                      float max_distance) {
  float t0 = 0.0f, t1 = max_distance;
  for (int k = 0; k < 3; ++k) {
    const float a = (lo[k] - origin[k]) * inv_dir[k], b = (hi[k] - origin[k]) * inv_dir[k];
    t0 = std::max(t0, std::min(a, b));
    t1 = std::min(t1, std::max(a, b));
  }
  return t0 <= t1 * kWiden + kSlack ? t0 : std::numeric_limits<float>::infinity();  // beyond(), in float
}

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
  centroids_.clear();
  centroids_.shrink_to_fit();
}

void RayCaster::build(uint32_t index, uint32_t first, uint32_t count, int depth) {
  Node node{glm::vec3(INFINITY), 0, glm::vec3(-INFINITY), 0};
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
// boundary that minimises area(left) * count(left) + area(right) * count(right), the expected cost of a random
// ray meeting the parent. Deterministic (no randomness, ties go to the first axis and bin); returns the left
// part's size, the part placed first in order_.
uint32_t RayCaster::split(uint32_t first, uint32_t count, const glm::vec3& cmin, const glm::vec3& cmax) {
  constexpr int kBins = 16;
  struct Bin {
    glm::vec3 lo{INFINITY}, hi{-INFINITY};
    uint32_t n = 0;
  };
  auto bin_of = [&](uint32_t t, int axis) {
    const float scale = float(kBins) / (cmax[axis] - cmin[axis]);
    return std::min(kBins - 1, static_cast<int>((centroids_[t][axis] - cmin[axis]) * scale));
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
      side = {glm::min(side.lo, bins[size_t(b)].lo), glm::max(side.hi, bins[size_t(b)].hi), side.n + bins[size_t(b)].n};
      right_cost[size_t(b)] = side.n ? surface_area(side.lo, side.hi) * float(side.n) : 0.0f;
    }
    side = Bin{};
    for (int b = 0; b + 1 < kBins; ++b) {
      side = {glm::min(side.lo, bins[size_t(b)].lo), glm::max(side.hi, bins[size_t(b)].hi), side.n + bins[size_t(b)].n};
      const float cost = (side.n ? surface_area(side.lo, side.hi) * float(side.n) : 0.0f) + right_cost[size_t(b) + 1];
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
uint32_t RayCaster::median_split(uint32_t first, uint32_t count, const glm::vec3& cmin, const glm::vec3& cmax) {
  const glm::vec3 extent = cmax - cmin;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const uint32_t half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](uint32_t a, uint32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
  return half;
}

template <typename OnTriangle>
void RayCaster::traverse(const glm::dvec3& origin, const glm::dvec3& dir, double max_distance, OnTriangle on) const {
  if (nodes_.empty()) return;
  const glm::vec3 origin_f(origin);
  bool in_float = glm::dvec3(origin_f) == origin;
  for (int k = 0; k < 3; ++k) in_float = in_float && std::fabs(dir[k]) >= kFloatParallel;
  const glm::dvec3 inv(1.0 / dir.x, 1.0 / dir.y, 1.0 / dir.z);
  if (in_float) {
    const glm::vec3 inv_f(inv);
    walk(max_distance, [&](const Node& n, double limit) -> double {
      return enter_box_float(n.min, n.max, origin_f, inv_f, static_cast<float>(limit));
    }, on);
  } else {
    walk(max_distance, [&](const Node& n, double limit) { return enter_box(n.min, n.max, origin, inv, limit); }, on);
  }
}

// Each node's box is tested once, when its parent is visited; the entry distance travels with it on the stack, so
// that closest() skips a node that a nearer hit has since put beyond reach.
template <typename BoxTest, typename OnTriangle>
void RayCaster::walk(double max_distance, BoxTest enter, OnTriangle on) const {
  struct Entry {
    uint32_t node;
    double entry;
  };
  Entry stack[128];
  int top = 0;
  const double root = enter(nodes_[0], max_distance);
  if (root == kMissed) return;
  stack[top++] = {0, root};
  while (top > 0) {
    const Entry e = stack[--top];
    if (beyond(e.entry, max_distance)) continue;
    const Node& node = nodes_[e.node];
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        max_distance = on(order_[i], max_distance);
        if (max_distance < 0) return;
      }
      continue;
    }
    Entry near{node.first, enter(nodes_[node.first], max_distance)};
    Entry far{node.first + 1, enter(nodes_[node.first + 1], max_distance)};
    if (far.entry < near.entry) std::swap(near, far);
    if (far.entry != kMissed) stack[top++] = far;  // the nearer child on top: closest() shrinks max_distance early
    if (near.entry != kMissed) stack[top++] = near;
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

glm::vec3 RayCaster::color_at(const Hit& h) const { return vertices_[3 * static_cast<size_t>(h.triangle)]->color; }

}  // namespace omnishadow::reference
