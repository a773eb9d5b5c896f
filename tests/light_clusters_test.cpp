// Clustered light lists against the brute force: over random cameras, frames and lights, every light within
// range of a point the camera sees is in the list of the point's cluster, the lists keep the scene's order,
// and they are short of the light count where ranges are local.

#include "backends/common/light_clusters.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <random>

namespace omnishadow {
namespace {

// The cluster words of cluster c: its lights, in list order.
std::vector<uint32_t> listed(const std::vector<uint32_t>& words, int c) {
  const uint32_t first = words[gpu::kClusterHeaderWords + 2 * size_t(c)];
  const uint32_t count = words[gpu::kClusterHeaderWords + 2 * size_t(c) + 1];
  return {words.begin() + first, words.begin() + first + count};
}

TEST(LightClusters, NoLightThatReachesAVisiblePointIsLeftOut) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), zero_one(0.0f, 1.0f);
  uint64_t checked = 0, listed_total = 0, points = 0;
  for (int trial = 0; trial < 60; ++trial) {
    scene::Camera camera;
    camera.position = 10.0f * glm::vec3(unit(rng), unit(rng), unit(rng));
    camera.target = camera.position + glm::vec3(unit(rng), unit(rng), unit(rng));
    camera.fov_y_degrees = 30.0f + 60.0f * zero_one(rng);
    camera.far_plane = 20.0f + 80.0f * zero_one(rng);
    const int width = 64 + int(400 * zero_one(rng)), height = 64 + int(300 * zero_one(rng));
    const gpu::ClusterGrid grid = gpu::cluster_grid(camera, width, height);
    std::vector<gpu::ClusterLight> lights;
    for (int k = 0; k < 40; ++k)
      lights.push_back({camera.position + 25.0f * glm::vec3(unit(rng), unit(rng), unit(rng)),
                        1.0f + 8.0f * zero_one(rng)});
    const std::vector<uint32_t> words = gpu::build_light_clusters(grid, lights);
    ASSERT_LE(words.size(), gpu::light_cluster_words(grid, int(lights.size())));
    for (int c = 0; c < grid.clusters(); ++c) {
      const std::vector<uint32_t> list = listed(words, c);
      ASSERT_TRUE(std::is_sorted(list.begin(), list.end())) << "the scene's order";
    }
    // Points at pixel centres, at random depths in the view: the lighting pass's pixels.
    const cube::ViewVolume& v = grid.view;
    for (int i = 0; i < 3000; ++i) {
      const int x = int(zero_one(rng) * float(width - 1)), y = int(zero_one(rng) * float(height - 1));
      const float z = v.near_plane + (v.far_plane - v.near_plane) * zero_one(rng) * zero_one(rng);
      const float ndc_x = -1.0f + 2.0f * (float(x) + 0.5f) / float(width);
      const float ndc_y = -1.0f + 2.0f * (float(y) + 0.5f) / float(height);
      const glm::vec3 p =
          v.eye + z * v.forward + ndc_x * z * v.tan_half_x * v.right + ndc_y * z * v.tan_half_y * v.up;
      const std::vector<uint32_t> list = listed(words, gpu::cluster_of(grid, x, y, p));
      ++points;
      listed_total += list.size();
      for (uint32_t k = 0; k < lights.size(); ++k) {
        if (glm::length(p - lights[k].position) >= lights[k].range) continue;
        ++checked;
        ASSERT_TRUE(std::binary_search(list.begin(), list.end(), k))
            << "trial " << trial << ": light " << k << " reaches pixel (" << x << ", " << y << ") at depth "
            << z << " but its cluster does not list it";
      }
    }
  }
  EXPECT_GT(checked, 1000u);
  EXPECT_LT(double(listed_total) / double(points), 20.0) << "lists much shorter than the 40 lights";
}

TEST(LightClusters, TheHeaderDescribesTheGrid) {
  scene::Camera camera;
  camera.near_plane = 0.5f;
  camera.far_plane = 50.0f;
  const gpu::ClusterGrid grid = gpu::cluster_grid(camera, 200, 100);
  EXPECT_EQ(grid.tiles_x, 4);  // 200 / 64, rounded up
  EXPECT_EQ(grid.tiles_y, 2);
  const std::vector<uint32_t> words = gpu::build_light_clusters(grid, std::vector<gpu::ClusterLight>{});
  EXPECT_EQ(words[0], 4u);
  EXPECT_EQ(words[1], 2u);
  EXPECT_EQ(words[2], uint32_t(gpu::kClusterSlices));
  EXPECT_EQ(words[3], uint32_t(gpu::kClusterTilePixels));
  EXPECT_EQ(std::bit_cast<float>(words[7]), 0.5f);
  EXPECT_EQ(words.size(), gpu::kClusterHeaderWords + 2 * size_t(grid.clusters()));
  // Depths before the near plane and beyond the far one fall into the first and last slices.
  const glm::vec3 near_point = camera.position + 0.01f * grid.view.forward;
  const glm::vec3 far_point = camera.position + 500.0f * grid.view.forward;
  EXPECT_EQ(gpu::cluster_of(grid, 0, 0, near_point), 0);
  EXPECT_EQ(gpu::cluster_of(grid, 0, 0, far_point), (gpu::kClusterSlices - 1) * 8);
}

}  // namespace
}  // namespace omnishadow
