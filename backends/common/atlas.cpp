#include "backends/common/atlas.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <tuple>

namespace omnishadow::atlas {

Texel face_origin(const Block& block, int face) {
  const int span = tile_span(block.face_size);
  return {block.x + (face % 3) * span + kBorder, block.y + (face / 3) * span + kBorder};
}

namespace {
// Blocks in `order` on shelves of at most `row_width` texels (a block wider than that alone on its shelf).
Plan shelves(std::span<const int> face_sizes, const std::vector<size_t>& order, int row_width) {
  Plan plan;
  plan.lights.resize(face_sizes.size());
  int x = 0, y = 0, row_height = 0;
  for (size_t k : order) {
    const int s = face_sizes[k];
    if (x > 0 && x + block_width(s) > row_width) {  // next shelf
      y += row_height;
      x = 0;
      row_height = 0;
    }
    plan.lights[k] = {x, y, s};
    x += block_width(s);
    row_height = std::max(row_height, block_height(s));
    plan.width = std::max(plan.width, x);
  }
  plan.height = y + row_height;
  return plan;
}
}  // namespace

Plan pack(std::span<const int> face_sizes) {
  if (face_sizes.empty()) throw std::invalid_argument("an atlas needs at least one light");
  for (int s : face_sizes)
    if (s < 1) throw std::invalid_argument("an atlas face size must be at least 1, got " + std::to_string(s));
  std::vector<size_t> order(face_sizes.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return face_sizes[a] > face_sizes[b]; });
  // Shelves as wide as 1, 2, ... of the largest block: the plan whose longer side is shortest (what a
  // device's largest 2D texture bounds), then the smallest area, then the narrowest.
  const int widest = block_width(face_sizes[order[0]]);
  Plan best;
  for (size_t n = 1; n <= face_sizes.size(); ++n) {
    Plan p = shelves(face_sizes, order, int(n) * widest);
    const bool one_shelf = p.width < int(n) * widest;  // wider shelves change nothing more
    const auto key = [](const Plan& q) {
      return std::make_tuple(std::max(q.width, q.height), 1LL * q.width * q.height, q.width);
    };
    if (best.lights.empty() || key(p) < key(best)) best = std::move(p);
    if (one_shelf) break;
  }
  return best;
}

double distance_over_range(const scene::Scene& scene, int light) {
  const scene::PointLight& l = scene.point_lights.at(size_t(light));
  return double(glm::length(l.path.at(0) - scene.camera.position)) / double(l.far_plane);
}

std::vector<int> face_sizes(const CaseConfig& config, const scene::Scene& scene) {
  std::vector<int> sizes(static_cast<size_t>(std::max(config.light_count, 1)), config.cube_size);
  if (config.atlas_tiles == AtlasTiles::uniform) return sizes;
  if (scene.point_lights.size() < sizes.size())
    throw std::logic_error("atlas sizes for " + std::to_string(sizes.size()) + " lights of a scene with " +
                           std::to_string(scene.point_lights.size()));
  for (size_t k = 0; k < sizes.size(); ++k) {
    const double ratio = distance_over_range(scene, int(k));
    const int halvings = ratio <= 1.0 ? 0 : std::clamp(int(std::lround(std::log2(ratio))), 0, kMaxHalvings);
    sizes[k] = std::max(1, config.cube_size >> halvings);
  }
  return sizes;
}

Plan plan_for(const CaseConfig& config, const scene::Scene& scene) { return pack(face_sizes(config, scene)); }

Plan uniform_plan(const CaseConfig& config) {
  return pack(std::vector<int>(static_cast<size_t>(std::max(config.light_count, 1)), config.cube_size));
}

std::string too_large(const Plan& plan, int max_size, const std::string& limit) {
  if (plan.width <= max_size && plan.height <= max_size) return {};
  return "an atlas of " + std::to_string(plan.lights.size()) + " light(s) takes " +
         std::to_string(plan.width) + "x" + std::to_string(plan.height) + " texels, above the device's " +
         std::to_string(max_size) + " (" + limit + ")";
}

}  // namespace omnishadow::atlas
