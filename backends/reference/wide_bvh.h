#pragma once
// The ray caster's hierarchy as traversed: four children a node, their boxes side by side so that one vector
// operation tests all four, collapsed from the binary SAH build (ray_caster.cpp). The box tests live here
// with the proof that they never miss a box the ray meets.

#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>
#include <limits>
#include <vector>

namespace omnishadow::reference {

struct BinaryNode {
  glm::vec3 min;
  uint32_t
      first;  // leaf: first index into the triangle order; inner: index of the left child (right = left + 1)
  glm::vec3 max;
  uint32_t count;  // leaf: triangle count; inner: 0
};

inline constexpr uint32_t kEmptyLane = 0xffffffffu;
struct alignas(16) WideNode {
  float lo[3][4], hi[3][4];  // per axis, the four children's bounds
  uint32_t child[4];         // inner child: index into the wide nodes; leaf child: first index into the order
  uint32_t count[4];         // leaf child: triangle count; inner child: 0; unused lane: kEmptyLane
};

// Node 0 is the root. Each wide node opens the binary node's children with the largest surface area first,
// until it holds four or only leaves.
std::vector<WideNode> collapse_to_wide(const std::vector<BinaryNode>& binary);

// Directions whose every component is at least this large in magnitude (and float origins) take the float
// test.
inline constexpr double kFloatParallel = 1e-12;
// Boxes are tested in float, four at a time, and conservatively: the test never misses a box the double ray
// meets within [0, max_distance]. The origin converts exactly (the caller checks it is a float), and each
// direction component is at least kFloatParallel, so |inv| <= 1e12 and no slab distance is NaN. Each slab
// distance then carries at most three roundings (1/dir to float, lo - o, the product): relative error (1 +
// u)^3 with u = 2^-24, except where lo - o is subnormal, which the subtraction gives exactly and the product
// rounds by at most 2^-149 absolute. The entry t0 is thus at most (1 + u)^3 high and the exit t1 (or
// float(max_distance)) at most (1 + u)^3 low, so a box the exact ray meets (t0 <= t1) has t0_f <= t1_f * (1 +
// u)^3 / (1 - u)^3, about 1 + 6u; the test allows t1_f * kWiden + kSlack, whose product rounds by one more u:
// kWiden = 1 + 2^-20 = 1 + 16u leaves a margin of more than 8u, and kSlack (1e-30) covers the subnormal
// roundings. The same allowance covers the triangle test's own rounding (a vertex on a box's face whose
// computed distance is a few double ulps short of the exact one) and the double test's (the same three
// roundings with u = 2^-53).
inline constexpr float kWiden = 1.0f + 0x1p-20f;
inline constexpr float kSlack = 1e-30f;

// True when a node entered at `entry` lies beyond `limit`, within the allowance that keeps the box tests
// conservative (below).
inline bool beyond(double entry, double limit) { return entry > limit * double(kWiden) + double(kSlack); }

// Entry distance per lane within [0, max_distance], +infinity where the lane's box is missed or the lane is
// unused. Float (inline: the traversal's inner loop): origin exactly a float, |inv| <= 1 / kFloatParallel.
inline void enter_wide(const WideNode& n, const glm::vec3& origin, const glm::vec3& inv_dir,
                       float max_distance, double entry[4]) {
  using Float4 = float __attribute__((vector_size(16)));  // SSE or NEON, whichever the compiler targets
  auto load = [](const float* p) {
    Float4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  auto vmin = [](Float4 a, Float4 b) { return a < b ? a : b; };
  auto vmax = [](Float4 a, Float4 b) { return a > b ? a : b; };
  Float4 t0 = {0.0f, 0.0f, 0.0f, 0.0f}, t1 = {max_distance, max_distance, max_distance, max_distance};
  for (int k = 0; k < 3; ++k) {
    const Float4 a = (load(n.lo[k]) - origin[k]) * inv_dir[k], b = (load(n.hi[k]) - origin[k]) * inv_dir[k];
    t0 = vmax(t0, vmin(a, b));
    t1 = vmin(t1, vmax(a, b));
  }
  const Float4 reach = t1 * kWiden + kSlack;  // beyond(), in float
  for (int lane = 0; lane < 4; ++lane)
    entry[lane] = t0[lane] <= reach[lane] && n.count[lane] != kEmptyLane
                      ? double(t0[lane])
                      : std::numeric_limits<double>::infinity();
}
// Double, for the rays the float test cannot take: NaN slabs (a ray in a slab's plane) do not reject.
void enter_wide(const WideNode& n, const glm::dvec3& origin, const glm::dvec3& inv_dir, double max_distance,
                double entry[4]);

}  // namespace omnishadow::reference
