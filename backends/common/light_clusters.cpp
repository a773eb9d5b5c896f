#include "backends/common/light_clusters.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace omnishadow::gpu {

ClusterGrid cluster_grid(const scene::Camera& camera, int width, int height) {
  ClusterGrid g;
  g.view = cube::camera_view(camera, width, height);
  g.width = std::max(width, 1);
  g.height = std::max(height, 1);
  g.tiles_x = (g.width + kClusterTilePixels - 1) / kClusterTilePixels;
  g.tiles_y = (g.height + kClusterTilePixels - 1) / kClusterTilePixels;
  g.slice_scale = float(g.slices) / std::log(g.view.far_plane / g.view.near_plane);
  return g;
}

namespace {

// Slice of view depth z, as the shader computes it (clamped into the grid).
int slice_of(const ClusterGrid& g, float z) {
  const float s = std::floor(std::log(std::max(z, g.view.near_plane) / g.view.near_plane) * g.slice_scale);
  return std::clamp(int(s), 0, g.slices - 1);
}

// Slice s's depths, the first from 0 and the last to infinity (the shader clamps depths beyond the grid into
// them), widened by a relative 1e-3 for the rounding of a depth near a boundary.
void slice_depths(const ClusterGrid& g, int s, float& z0, float& z1) {
  z0 = s == 0 ? 0.0f : g.view.near_plane * std::exp(float(s) / g.slice_scale) * (1.0f - 1e-3f);
  z1 = s == g.slices - 1 ? INFINITY
                         : g.view.near_plane * std::exp(float(s + 1) / g.slice_scale) * (1.0f + 1e-3f);
}

// NDC of tile edge `edge` (0 .. tiles) along an axis of `pixels`: tile k spans pixels [k T, (k + 1) T).
float tile_ndc(int edge, int pixels) {
  return -1.0f + 2.0f * float(std::min(edge * kClusterTilePixels, pixels)) / float(pixels);
}

// The distance along one screen axis from view coordinate v to tile `tile`'s extent between depths z0 and z1
// (the box is separable: its squared distance from a point is the sum of the three axes' squares).
float axis_distance(int tile, int pixels, float tan_half, float z0, float z1, float v) {
  const float margin = 1e-3f * z1;
  const float ndc0 = tile_ndc(tile, pixels), ndc1 = tile_ndc(tile + 1, pixels);
  const float lo = std::min(ndc0 * tan_half * z0, ndc0 * tan_half * z1) - margin;
  const float hi = std::max(ndc1 * tan_half * z0, ndc1 * tan_half * z1) + margin;
  return v < lo ? lo - v : v > hi ? v - hi : 0.0f;
}

// The tiles [lo, hi] along an axis that a sphere (view coordinate v, depth cz, radius r) may cover between
// depths z0 and z1 > 0: v / z is monotonic in z, so its extremes lie at the two depths.
void tile_span(float v, float r, float z0, float z1, float tan_half, int pixels, int tiles, int& lo,
               int& hi) {
  const float a = std::min({(v - r) / z0, (v - r) / z1}) / tan_half;
  const float b = std::max({(v + r) / z0, (v + r) / z1}) / tan_half;
  auto tile = [&](float ndc) {
    return std::clamp(int(std::floor((ndc + 1.0f) * 0.5f * float(pixels) / kClusterTilePixels)), 0,
                      tiles - 1);
  };
  lo = tile(std::max(a, -1.0f) - 1e-3f);
  hi = tile(std::min(b, 1.0f) + 1e-3f);
}

}  // namespace

size_t light_cluster_words(const ClusterGrid& grid, int lights) {
  return kClusterHeaderWords + size_t(grid.clusters()) * (2 + size_t(std::max(lights, 0)));
}

// Every (cluster, light) pair whose light's range reaches the cluster's box, lights in the scene's order.
static void reached_clusters(const ClusterGrid& g, const std::vector<ClusterLight>& lights,
                             std::vector<std::pair<uint32_t, uint32_t>>& pairs) {
  std::vector<float> dx2;  // per tile of the span: the x axis's squared distance
  for (uint32_t k = 0; k < lights.size(); ++k) {
    const glm::vec3 d = lights[k].position - g.view.eye;
    const glm::vec3 c(glm::dot(d, g.view.right), glm::dot(d, g.view.up), glm::dot(d, g.view.forward));
    const float r = lights[k].range * (1.0f + 1e-4f);
    if (c.z + r < g.view.near_plane * (1.0f - 1e-3f)) continue;  // wholly before the near plane
    const int s_lo = slice_of(g, c.z - r), s_hi = slice_of(g, c.z + r);
    for (int s = s_lo; s <= s_hi; ++s) {
      float z0 = 0.0f, z1 = 0.0f;
      slice_depths(g, s, z0, z1);
      z0 = std::max(z0, std::max(c.z - r, g.view.near_plane * (1.0f - 1e-3f)));
      z1 = std::min(z1, c.z + r);
      if (z0 > z1) continue;
      int x_lo = 0, x_hi = 0, y_lo = 0, y_hi = 0;
      tile_span(c.x, r, z0, z1, g.view.tan_half_x, g.width, g.tiles_x, x_lo, x_hi);
      tile_span(c.y, r, z0, z1, g.view.tan_half_y, g.height, g.tiles_y, y_lo, y_hi);
      const float dz = c.z < z0 ? z0 - c.z : c.z > z1 ? c.z - z1 : 0.0f;
      dx2.clear();
      for (int tx = x_lo; tx <= x_hi; ++tx) {
        const float dx = axis_distance(tx, g.width, g.view.tan_half_x, z0, z1, c.x);
        dx2.push_back(dx * dx);
      }
      for (int ty = y_lo; ty <= y_hi; ++ty) {
        const float dy = axis_distance(ty, g.height, g.view.tan_half_y, z0, z1, c.y);
        const float left = r * r - dy * dy - dz * dz;  // what the x axis may still add
        if (left < 0.0f) continue;
        for (int tx = x_lo; tx <= x_hi; ++tx)
          if (dx2[size_t(tx - x_lo)] <= left)
            pairs.emplace_back(uint32_t((s * g.tiles_y + ty) * g.tiles_x + tx), k);
      }
    }
  }
}

const std::vector<uint32_t>& LightClusterBuilder::build(const std::vector<ClusterLight>& lights) {
  const ClusterGrid& g = grid_;
  pairs_.clear();
  reached_clusters(g, lights, pairs_);
  const size_t clusters = size_t(g.clusters()), lists = kClusterHeaderWords + 2 * clusters;
  words_.assign(lists + pairs_.size(), 0u);
  words_[0] = uint32_t(g.tiles_x);
  words_[1] = uint32_t(g.tiles_y);
  words_[2] = uint32_t(g.slices);
  words_[3] = uint32_t(kClusterTilePixels);
  for (int i = 0; i < 3; ++i) words_[size_t(4 + i)] = std::bit_cast<uint32_t>(g.view.forward[i]);
  words_[7] = std::bit_cast<uint32_t>(g.view.near_plane);
  words_[8] = std::bit_cast<uint32_t>(g.slice_scale);
  // A counting sort by cluster, stable: each list keeps the scene's order.
  for (const auto& [cluster, light] : pairs_) ++words_[kClusterHeaderWords + 2 * cluster + 1];
  uint32_t next = uint32_t(lists);
  for (size_t c = 0; c < clusters; ++c) {
    words_[kClusterHeaderWords + 2 * c] = next;
    next += words_[kClusterHeaderWords + 2 * c + 1];
  }
  filled_.assign(clusters, 0u);
  for (const auto& [cluster, light] : pairs_)
    words_[words_[kClusterHeaderWords + 2 * cluster] + filled_[cluster]++] = light;
  return words_;
}

const std::vector<uint32_t>& LightClusterBuilder::build(const scene::Camera& camera,
                                                        const std::vector<PointLightRecord>& records) {
  grid_.view = cube::camera_view(camera, grid_.width, grid_.height);
  lights_.clear();
  for (const PointLightRecord& r : records) lights_.push_back({glm::vec3(r.position_far), r.position_far.w});
  return build(lights_);
}

std::vector<uint32_t> build_light_clusters(const ClusterGrid& grid, const std::vector<ClusterLight>& lights) {
  LightClusterBuilder builder(grid);
  return builder.build(lights);
}

int cluster_of(const ClusterGrid& g, int x, int y, const glm::vec3& world) {
  const int tx = std::clamp(x / kClusterTilePixels, 0, g.tiles_x - 1);
  const int ty = std::clamp(y / kClusterTilePixels, 0, g.tiles_y - 1);
  const int s = slice_of(g, glm::dot(world - g.view.eye, g.view.forward));
  return (s * g.tiles_y + ty) * g.tiles_x + tx;
}

}  // namespace omnishadow::gpu
