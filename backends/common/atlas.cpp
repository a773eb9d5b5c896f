#include "backends/common/atlas.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <tuple>

#include "backends/common/view_culling.h"

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

// The lights largest block first (ties in light order), after checking the sizes.
std::vector<size_t> packing_order(std::span<const int> face_sizes) {
  if (face_sizes.empty()) throw std::invalid_argument("an atlas needs at least one light");
  for (int s : face_sizes)
    if (s < 1) throw std::invalid_argument("an atlas face size must be at least 1, got " + std::to_string(s));
  std::vector<size_t> order(face_sizes.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return face_sizes[a] > face_sizes[b]; });
  return order;
}

// pack's order of plans: the longer side shortest (what a device's largest 2D texture bounds), then the
// smallest area, then the narrowest.
auto plan_key(const Plan& q) {
  return std::make_tuple(std::max(q.width, q.height), 1LL * q.width * q.height, q.width);
}
}  // namespace

Plan pack(std::span<const int> face_sizes) {
  const std::vector<size_t> order = packing_order(face_sizes);
  // Shelves as wide as 1, 2, ... of the largest block.
  const int widest = block_width(face_sizes[order[0]]);
  Plan best;
  for (size_t n = 1; n <= face_sizes.size(); ++n) {
    Plan p = shelves(face_sizes, order, int(n) * widest);
    const bool one_shelf = p.width < int(n) * widest;  // wider shelves change nothing more
    if (best.lights.empty() || plan_key(p) < plan_key(best)) best = std::move(p);
    if (one_shelf) break;
  }
  return best;
}

// The atlas's own width is a candidate: with it, blocks no wider than a uniform atlas's fill at least as many
// to a row as it holds, on rows no taller, so that a by_distance re-plan always fits the uniform rectangle.
std::optional<Plan> pack_into(std::span<const int> face_sizes, int width, int height) {
  const std::vector<size_t> order = packing_order(face_sizes);
  const int widest = block_width(face_sizes[order[0]]);
  std::vector<int> rows{width};
  for (int n = 1; n <= int(face_sizes.size()) && n * widest < width; ++n) rows.push_back(n * widest);
  std::optional<Plan> best;
  for (int row : rows) {
    Plan p = shelves(face_sizes, order, row);
    if (p.width > width || p.height > height) continue;
    if (!best || plan_key(p) < plan_key(*best)) best = std::move(p);
  }
  if (best) std::tie(best->width, best->height) = std::tie(width, height);
  return best;
}

double distance_over_range(const scene::Scene& scene, int light, int frame) {
  const scene::PointLight& l = scene.point_lights.at(size_t(light));
  return double(glm::length(l.path.at(frame) - scene.camera.at(frame).position)) / double(l.far_plane);
}

double screen_coverage(const scene::Scene& scene, int light, int width, int height, int frame) {
  const scene::PointLight& l = scene.point_lights.at(size_t(light));
  const cube::ViewVolume v = cube::camera_view(scene.camera.at(frame), width, height);
  const glm::vec3 p = l.path.at(frame);
  const float r = l.far_plane;
  if (glm::length(p - v.eye) <= r) return 1.0;  // the camera inside the range: it fills the view
  if (cube::view_face_mask(v, p, r, {}, 1, false) == 0) return 0.0;
  const glm::vec3 d = p - v.eye;
  const glm::vec3 c(glm::dot(d, v.right), glm::dot(d, v.up), glm::dot(d, v.forward));
  const float z = std::max(c.z - r, v.near_plane);  // the sphere's nearest depth: its widest projection
  auto extent = [&](float centre, float tan_half) {
    const float lo = std::max((centre - r) / (z * tan_half), -1.0f);
    const float hi = std::min((centre + r) / (z * tan_half), 1.0f);
    return std::max(hi - lo, 0.0f) / 2.0f;
  };
  return double(extent(c.x, v.tan_half_x)) * double(extent(c.y, v.tan_half_y));
}

namespace {

// A lamp's size at a re-plan with hysteresis (CaseConfig::atlas_hysteresis_octaves): `held`, the size it
// has, while the rule's sizes for its need scaled by 2^-H and by 2^H bracket it (a need within H octaves of
// one that gives the held size keeps it); else the rule's size for the need itself. size_at(f): the rule's
// size for the need times f, never decreasing in f, so that neither does the result in the need.
template <class SizeAt>
int held_or_fresh(int held, double octaves, SizeAt size_at) {
  if (held > 0 && octaves > 0.0) {
    const double by = std::exp2(octaves);
    if (size_at(1.0 / by) <= held && held <= size_at(by)) return held;
  }
  return size_at(1.0);
}

int coverage_size(const CaseConfig& config, double ideal) {
  int size = kMinCoverageFace;
  while (size * 2 <= std::min(ideal, double(config.cube_size))) size *= 2;
  return std::min(size, config.cube_size);
}

// by_distance: --cube halved round(log2(ratio)) times, at most kMaxHalvings (a need 1 / ratio).
int distance_size(const CaseConfig& config, double ratio) {
  const int halvings = ratio <= 1.0 ? 0 : std::clamp(int(std::lround(std::log2(ratio))), 0, kMaxHalvings);
  return std::max(1, config.cube_size >> halvings);
}

// by_coverage: face sizes t sqrt(coverage) rounded down to a power of two, between kMinCoverageFace and
// --cube, for the largest scale t (in steps of 2^(1/4)) whose sizes `fits` accepts; every light at the
// smallest when none does (budget_problem says so; scale 0).
struct CoverageSizes {
  std::vector<double> coverage;
  double scale = 0.0;
  std::vector<int> sizes;
};
template <class Fits>
CoverageSizes sizes_by_coverage(const CaseConfig& config, const scene::Scene& scene, size_t lights, int frame,
                                Fits fits) {
  CoverageSizes out{std::vector<double>(lights), 0.0, std::vector<int>(lights)};
  for (size_t k = 0; k < lights; ++k)
    out.coverage[k] = screen_coverage(scene, int(k), config.width, config.height, frame);
  for (double t = 16.0 * config.cube_size; t >= 1.0; t /= std::pow(2.0, 0.25)) {
    for (size_t k = 0; k < lights; ++k) out.sizes[k] = coverage_size(config, t * std::sqrt(out.coverage[k]));
    if (fits(out.sizes)) {
      out.scale = t;
      return out;
    }
  }
  out.sizes.assign(lights, std::min(kMinCoverageFace, config.cube_size));
  return out;
}

// by_coverage with hysteresis: the frame's scale and sizes (`fresh`), each light keeping its `held` size
// while that is within the band at that scale; where the held sizes then do not fit, the lights held above
// their fresh size give it up, the furthest above first (ties: the larger, then the lower light), until they
// do (all fresh fits). Holding relative to one frame's scale, rather than choosing the scale with the held
// sizes in it, keeps a step of the scale from moving every light at once, and a light held large from
// pushing the scale down until all the others drop out of their bands together.
template <class Fits>
std::vector<int> held_by_coverage(const CaseConfig& config, const CoverageSizes& fresh,
                                  std::span<const int> held, Fits fits) {
  std::vector<int> sizes = fresh.sizes;
  if (fresh.scale <= 0.0) return sizes;
  for (size_t k = 0; k < sizes.size() && k < held.size(); ++k) {
    const double ideal = fresh.scale * std::sqrt(fresh.coverage[k]);
    sizes[k] = held_or_fresh(held[k], config.atlas_hysteresis_octaves,
                             [&](double f) { return coverage_size(config, ideal * f); });
  }
  while (!fits(sizes)) {
    size_t give_up = sizes.size();
    for (size_t k = 0; k < sizes.size(); ++k) {
      if (sizes[k] == fresh.sizes[k]) continue;
      if (give_up == sizes.size()) {
        give_up = k;
        continue;
      }
      const auto key = [&](size_t j) { return std::make_tuple(double(sizes[j]) / fresh.sizes[j], sizes[j]); };
      if (key(k) > key(give_up)) give_up = k;
    }
    if (give_up == sizes.size()) break;  // all fresh: they fit
    sizes[give_up] = fresh.sizes[give_up];
  }
  return sizes;
}

// by_coverage within an allocated atlas: the scale rising on past the quarter step that fits. The light whose
// ideal at `fresh`'s scale is the largest multiple of its size (the next to reach its next size as the scale
// rises; ties: the lower light) doubles while the atlas holds it; one that does not fit stays for that pass,
// and the others go on; passes repeat until one grows nothing (shelves are not monotone in the sizes: a light
// refused early may fit after others grew), so that no light could double and still fit. A quarter step
// moves a share of the lights across a power of two at once, so the last step that fits can leave most of a
// kept rectangle empty (a re-plan's atlas does not shrink to its sizes, as frame 0's does). Lights out of
// view stay at the least; none grows past --cube.
template <class Fits>
void fill_by_coverage(const CaseConfig& config, const CoverageSizes& fresh, std::vector<int>& sizes,
                      Fits fits) {
  if (fresh.scale <= 0.0) return;
  for (bool grew = true; grew;) {
    grew = false;
    std::vector<uint8_t> stays(sizes.size(), 0);
    for (;;) {
      size_t grow = sizes.size();
      double most = 0.0;
      for (size_t k = 0; k < sizes.size(); ++k) {
        if (stays[k] || sizes[k] >= config.cube_size || fresh.coverage[k] <= 0.0) continue;
        const double multiple = fresh.scale * std::sqrt(fresh.coverage[k]) / sizes[k];
        if (multiple > most) most = multiple, grow = k;
      }
      if (grow == sizes.size()) break;
      sizes[grow] *= 2;
      if (fits(sizes)) {
        grew = true;
      } else {
        sizes[grow] /= 2;
        stays[grow] = 1;
      }
    }
  }
}

}  // namespace

uint64_t budget_texels(const CaseConfig& config) {
  if (config.shadow_budget_texels) return config.shadow_budget_texels;
  const Plan uniform = uniform_plan(config);
  return uint64_t(uniform.width) * uint64_t(uniform.height);
}

std::vector<int> face_sizes(const CaseConfig& config, const scene::Scene& scene, int frame) {
  std::vector<int> sizes(static_cast<size_t>(std::max(config.light_count, 1)), config.cube_size);
  if (config.atlas_tiles == AtlasTiles::uniform) return sizes;
  if (scene.point_lights.size() < sizes.size())
    throw std::logic_error("atlas sizes for " + std::to_string(sizes.size()) + " lights of a scene with " +
                           std::to_string(scene.point_lights.size()));
  if (config.atlas_tiles == AtlasTiles::by_coverage) {
    const uint64_t budget = budget_texels(config);
    return sizes_by_coverage(config, scene, sizes.size(), frame,
                             [&](const std::vector<int>& s) {
                               const Plan plan = pack(s);
                               return uint64_t(plan.width) * uint64_t(plan.height) <= budget;
                             })
        .sizes;
  }
  for (size_t k = 0; k < sizes.size(); ++k)
    sizes[k] = distance_size(config, distance_over_range(scene, int(k), frame));
  return sizes;
}

std::vector<int> face_sizes_within(const CaseConfig& config, const scene::Scene& scene, int frame, int width,
                                   int height, std::span<const int> held) {
  if (config.atlas_tiles == AtlasTiles::by_coverage) {
    const auto fits = [&](const std::vector<int>& s) { return pack_into(s, width, height).has_value(); };
    const CoverageSizes fresh =
        sizes_by_coverage(config, scene, size_t(std::max(config.light_count, 1)), frame, fits);
    std::vector<int> sizes = held.empty() ? fresh.sizes : held_by_coverage(config, fresh, held, fits);
    fill_by_coverage(config, fresh, sizes, fits);
    return sizes;
  }
  std::vector<int> sizes = face_sizes(config, scene, frame);
  if (config.atlas_tiles != AtlasTiles::by_distance) return sizes;
  for (size_t k = 0; k < sizes.size() && k < held.size(); ++k) {
    const double ratio = distance_over_range(scene, int(k), frame);
    sizes[k] = held_or_fresh(held[k], config.atlas_hysteresis_octaves,
                             [&](double f) { return distance_size(config, ratio / f); });
  }
  return sizes;
}

Plan plan_for(const CaseConfig& config, const scene::Scene& scene) {
  if (config.atlas_replan_frames <= 0 || config.atlas_tiles == AtlasTiles::uniform)
    return pack(face_sizes(config, scene));
  const Plan kept =
      config.atlas_tiles == AtlasTiles::by_distance ? uniform_plan(config) : pack(face_sizes(config, scene));
  return pack_frame(config, scene, 0, kept.width, kept.height);
}

std::string budget_problem(const CaseConfig& config) {
  if (config.layout != Layout::atlas || config.atlas_tiles != AtlasTiles::by_coverage) return {};
  const Plan plan = pack(std::vector<int>(size_t(std::max(config.light_count, 1)),
                                          std::min(kMinCoverageFace, config.cube_size)));
  const uint64_t texels = uint64_t(plan.width) * uint64_t(plan.height), budget = budget_texels(config);
  if (texels <= budget) return {};
  return "--shadow-budget " + std::to_string(budget) + " texels: " + std::to_string(config.light_count) +
         " lights' atlas takes " + std::to_string(texels) + " at the smallest tiles (" +
         std::to_string(kMinCoverageFace) + " texels a side)";
}

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
