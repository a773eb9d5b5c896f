#include "backends/reference/wide_bvh.h"

#include <algorithm>
#include <limits>

namespace omnishadow::reference {
namespace {

constexpr double kMissed = std::numeric_limits<double>::infinity();

float surface_area(const BinaryNode& n) {
  const glm::vec3 d = n.max - n.min;
  return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
}

uint32_t fill(std::vector<WideNode>& wide, const std::vector<BinaryNode>& binary, uint32_t root) {
  std::vector<uint32_t> kids;
  if (binary[root].count > 0)
    kids = {root};
  else
    kids = {binary[root].first, binary[root].first + 1};
  while (kids.size() < 4) {
    int open = -1;
    for (size_t i = 0; i < kids.size(); ++i)
      if (binary[kids[i]].count == 0 &&
          (open < 0 || surface_area(binary[kids[i]]) > surface_area(binary[kids[size_t(open)]])))
        open = int(i);
    if (open < 0) break;
    const uint32_t left = binary[kids[size_t(open)]].first;
    kids[size_t(open)] = left;
    kids.insert(kids.begin() + open + 1, left + 1);
  }
  const uint32_t index = static_cast<uint32_t>(wide.size());
  wide.emplace_back();
  WideNode node{};
  for (size_t lane = 0; lane < 4; ++lane) {
    node.count[lane] = kEmptyLane;
    if (lane >= kids.size()) continue;
    const BinaryNode& b = binary[kids[lane]];
    for (int k = 0; k < 3; ++k) {
      node.lo[k][lane] = b.min[k];
      node.hi[k][lane] = b.max[k];
    }
    node.count[lane] = b.count;
    node.child[lane] = b.count > 0 ? b.first : fill(wide, binary, kids[lane]);
  }
  wide[index] = node;  // after the children: they may have moved the vector
  return index;
}

}  // namespace

std::vector<WideNode> collapse_to_wide(const std::vector<BinaryNode>& binary) {
  std::vector<WideNode> wide;
  if (binary.empty()) return wide;
  wide.reserve(binary.size() / 2 + 1);
  fill(wide, binary, 0);
  return wide;
}

void enter_wide(const WideNode& n, const glm::dvec3& origin, const glm::dvec3& inv_dir, double max_distance,
                double entry[4]) {
  for (int lane = 0; lane < 4; ++lane) {
    double t0 = 0.0, t1 = max_distance;
    for (int k = 0; k < 3; ++k) {
      double a = (n.lo[k][lane] - origin[k]) * inv_dir[k];
      double b = (n.hi[k][lane] - origin[k]) * inv_dir[k];
      if (a > b) std::swap(a, b);
      // NaN (0 * inf for a ray in the slab's plane) must not reject: keep the current bounds.
      if (a > t0) t0 = a;
      if (b < t1) t1 = b;
    }
    entry[lane] = n.count[lane] == kEmptyLane || beyond(t0, t1) ? kMissed : t0;
  }
}

}  // namespace omnishadow::reference
