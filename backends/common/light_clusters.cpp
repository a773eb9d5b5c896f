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

// The squared distance from c to the view-space box of tile (tx, ty) between depths z0 and z1 (finite).
float box_distance2(const ClusterGrid& g, int tx, int ty, float z0, float z1, const glm::vec3& c) {
  const float margin = 1e-3f * z1;
  auto extent = [&](float ndc0, float ndc1, float tan_half, float v) {
    const float lo = std::min(ndc0 * tan_half * z0, ndc0 * tan_half * z1) - margin;
    const float hi = std::max(ndc1 * tan_half * z0, ndc1 * tan_half * z1) + margin;
    return v < lo ? lo - v : v > hi ? v - hi : 0.0f;
  };
  const float dx = extent(tile_ndc(tx, g.width), tile_ndc(tx + 1, g.width), g.view.tan_half_x, c.x);
  const float dy = extent(tile_ndc(ty, g.height), tile_ndc(ty + 1, g.height), g.view.tan_half_y, c.y);
  const float dz = c.z < z0 ? z0 - c.z : c.z > z1 ? c.z - z1 : 0.0f;
  return dx * dx + dy * dy + dz * dz;
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

std::vector<uint32_t> build_light_clusters(const ClusterGrid& g, const std::vector<ClusterLight>& lights) {
  std::vector<std::vector<uint32_t>> lists(size_t(g.clusters()));
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
      for (int ty = y_lo; ty <= y_hi; ++ty)
        for (int tx = x_lo; tx <= x_hi; ++tx)
          if (box_distance2(g, tx, ty, z0, z1, c) <= r * r)
            lists[size_t((s * g.tiles_y + ty) * g.tiles_x + tx)].push_back(k);
    }
  }
  std::vector<uint32_t> words(kClusterHeaderWords + 2 * lists.size(), 0u);
  words[0] = uint32_t(g.tiles_x);
  words[1] = uint32_t(g.tiles_y);
  words[2] = uint32_t(g.slices);
  words[3] = uint32_t(kClusterTilePixels);
  for (int i = 0; i < 3; ++i) words[size_t(4 + i)] = std::bit_cast<uint32_t>(g.view.forward[i]);
  words[7] = std::bit_cast<uint32_t>(g.view.near_plane);
  words[8] = std::bit_cast<uint32_t>(g.slice_scale);
  for (size_t c = 0; c < lists.size(); ++c) {
    words[kClusterHeaderWords + 2 * c] = uint32_t(words.size());
    words[kClusterHeaderWords + 2 * c + 1] = uint32_t(lists[c].size());
    words.insert(words.end(), lists[c].begin(), lists[c].end());
  }
  return words;
}

std::vector<uint32_t> build_light_clusters(const ClusterGrid& grid,
                                           const std::vector<PointLightRecord>& records) {
  std::vector<ClusterLight> lights;
  lights.reserve(records.size());
  for (const PointLightRecord& r : records) lights.push_back({glm::vec3(r.position_far), r.position_far.w});
  return build_light_clusters(grid, lights);
}

int cluster_of(const ClusterGrid& g, int x, int y, const glm::vec3& world) {
  const int tx = std::clamp(x / kClusterTilePixels, 0, g.tiles_x - 1);
  const int ty = std::clamp(y / kClusterTilePixels, 0, g.tiles_y - 1);
  const int s = slice_of(g, glm::dot(world - g.view.eye, g.view.forward));
  return (s * g.tiles_y + ty) * g.tiles_x + tx;
}

}  // namespace omnishadow::gpu
