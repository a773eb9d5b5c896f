// Every layout row's geometry holds together (backends/common/layouts.h): its layers store a cube's memory,
// each layer's view-projection lands the row's own texel rays on their texels at the axis distance the ray's
// depth_to_distance says, and a name for every layer. A row that paired one map's rays with another's
// matrices, or a layer count with the wrong names, fails here before any image is rendered.
#include "backends/common/layouts.h"

#include <gtest/gtest.h>

#include <cmath>

namespace omnishadow {
namespace {

TEST(LayoutRows, EveryLayoutStoresACubesMemory) {
  for (const LayoutTraits& row : kLayouts)
    for (int n : {64, 512, 1024}) {
      const double edge = layer_size(row.layout, n);
      EXPECT_NEAR(row.geometry.layers * edge * edge / (6.0 * n * n), 1.0, 0.01) << row.name << " at " << n;
    }
}

TEST(LayoutRows, EveryLayerHasAName) {
  for (const LayoutTraits& row : kLayouts) {
    ASSERT_EQ(row.geometry.layer_names.size(), size_t(row.geometry.layers)) << row.name;
    for (const char* name : row.geometry.layer_names)
      EXPECT_GT(std::string_view(name).size(), 0u) << row.name;
  }
}

// A perspective layer's matrix takes the point `distance` along its texel ray to that texel, with clip w (the
// axis distance) = distance / depth_to_distance. The paraboloid's layers are warped in the vertex stage
// (shaders/paraboloid.glsl; tests/paraboloid_test.cpp), not by a matrix: its rays are unit and radial.
TEST(LayoutRows, LayerMatricesLandTheRowsOwnRaysOnTheirTexels) {
  const glm::vec3 light(0.5f, -1.0f, 2.0f);
  const int size = 32;
  const double distance = 3.0;
  for (const LayoutTraits& row : kLayouts)
    for (int f = 0; f < row.geometry.layers; ++f)
      for (double s : {0.5, 9.25, 16.0, 31.5})
        for (double t : {0.5, 20.75, 31.5}) {
          const std::optional<LayerRay> ray = row.geometry.point_ray(f, s, t, size);
          ASSERT_TRUE(ray || row.geometry.clips_to_hemisphere) << row.name << " layer " << f;
          if (!ray) continue;
          EXPECT_NEAR(glm::length(ray->unit), 1.0, 1e-12) << row.name;
          if (row.geometry.map == TexelMap::paraboloid) {
            EXPECT_EQ(ray->depth_to_distance, 1.0) << "radial depth";
            continue;
          }
          const glm::mat4 m =
              row.geometry.view_projection(f, light, 0.1f, 50.0f, cube::DepthRange::zero_to_one);
          const glm::vec4 clip = m * glm::vec4(light + glm::vec3(ray->unit * distance), 1.0f);
          EXPECT_NEAR(clip.x / clip.w, 2.0 * s / size - 1.0, 1e-5) << row.name << " layer " << f;
          EXPECT_NEAR(clip.y / clip.w, 2.0 * t / size - 1.0, 1e-5) << row.name << " layer " << f;
          EXPECT_NEAR(clip.w, distance / ray->depth_to_distance, 1e-5) << row.name << " layer " << f;
        }
}

}  // namespace
}  // namespace omnishadow
