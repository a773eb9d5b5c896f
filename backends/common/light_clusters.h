#pragma once
// Clustered light lists (--optimize clusters), as forward+ and clustered renderers build them (Filament's
// froxels): the view is cut into screen tiles of kClusterTilePixels and kClusterSlices slices of view depth
// (exponential between the camera's near and far), and each cluster lists the point lights whose range sphere
// reaches its box, in the scene's order. The lighting pass shades a pixel with its cluster's lights only, in
// that order, so its sum is the loop over every light's without the lights that add nothing there.
//
// Built on the CPU each frame (the lights move) and uploaded as one std430 uint array, the layout
// shaders/lighting.frag reads (LightClusters):
//   words[0..3]   tiles across, tiles up, slices, tile size in pixels
//   words[4..6]   the camera's unit forward vector (float bits), words[7] near, words[8] slices / ln(far /
//   near) words[kClusterHeaderWords + 2c], [+ 2c + 1]: cluster c's first index word and its light count then
//   the light indices. Cluster c = (slice * tiles up + tile y) * tiles across + tile x; tile row 0 is the
//   frame's first row in memory (clip y = -1, both APIs: cube_faces.h), slice 0 the nearest.
//
// Conservative by construction: each cluster's test box holds its part of the view frustum, widened by a
// relative 1e-3 for the rounding of the shader's slice and of the interpolated position, so no light that
// reaches a pixel is left out of the pixel's list (bench/truth checks it against every light's distance).

#include <cstdint>
#include <glm/glm.hpp>
#include <utility>
#include <vector>

#include "backends/common/gpu_layout.h"
#include "backends/common/view_culling.h"
#include "scenes/scene.h"

namespace omnishadow::gpu {

inline constexpr int kClusterTilePixels = 64;
inline constexpr int kClusterSlices = 16;
inline constexpr uint32_t kClusterHeaderWords = 16;

struct ClusterGrid {
  cube::ViewVolume view;      // the camera's frustum (backends/common/view_culling.h)
  int width = 1, height = 1;  // the frame, pixels
  int tiles_x = 1, tiles_y = 1, slices = kClusterSlices;
  float slice_scale = 1.0f;  // slices / ln(far / near)
  int clusters() const { return tiles_x * tiles_y * slices; }
};
ClusterGrid cluster_grid(const scene::Camera& camera, int width, int height);

// A point light as the lighting pass sees it: position and range (its far plane).
struct ClusterLight {
  glm::vec3 position;
  float range;
};

// The uploaded words (layout above) for `lights` in the scene's order.
std::vector<uint32_t> build_light_clusters(const ClusterGrid& grid, const std::vector<ClusterLight>& lights);

// The same frame after frame over one grid, its buffers kept: a frame's lists at 1080p are megabytes, and
// allocated afresh each frame their first touch costs more than building them.
class LightClusterBuilder {
 public:
  explicit LightClusterBuilder(const ClusterGrid& grid = {}) : grid_(grid) {}
  const std::vector<uint32_t>& build(const std::vector<ClusterLight>& lights);
  // From the lighting pass's records (their position and far plane), for the frame seen through `camera`: a
  // moving camera takes the grid along (its tiles and slices stay; its frustum is the frame's).
  const std::vector<uint32_t>& build(const scene::Camera& camera,
                                     const std::vector<PointLightRecord>& records);
  const ClusterGrid& grid() const { return grid_; }

 private:
  ClusterGrid grid_;
  std::vector<std::pair<uint32_t, uint32_t>> pairs_;  // (cluster, light), lights in the scene's order
  std::vector<uint32_t> filled_, words_;
  std::vector<ClusterLight> lights_;
};
// The most words build_light_clusters can write for `lights` lights (the buffer's size).
size_t light_cluster_words(const ClusterGrid& grid, int lights);

// The cluster of pixel (x, y) (row 0 first in memory) whose surface lies at `world`: the shader's arithmetic.
int cluster_of(const ClusterGrid& grid, int x, int y, const glm::vec3& world);

}  // namespace omnishadow::gpu
