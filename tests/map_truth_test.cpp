// The 2D maps' texel truth (spot and directional lights), without a device: the judge's allowance for a
// fragment that covered its centre from a point of the reach square past a steep triangle's edge.

#include "bench/truth/map_truth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_inverse.hpp>

#include "backends/common/map_lights.h"

namespace omnishadow::bench {
namespace {

// A spot light at the origin looking down +X onto one steep triangle whose edge runs between texel (4, 4)'s
// centre and its left corners, 1/256 texel from the centre, at window depth 0.9; its far vertex, at the map's
// right edge, sits at 0.5: about 0.1 of window depth a texel, ten times the 1e-5 the agreement allows over
// the reach. The texel may hold the depth at the edge, which no corner holds (the left ones meet nothing); it
// may not hold the plane's depth one step beyond the reach square.
TEST(MapTruth, ASteepEdgeInsideTheReachSquareBoundsByItsPlane) {
  constexpr int kSize = 8, kBits = 8;
  const double step = std::ldexp(1.0, -kBits), edge = 4.5 - step;
  scene::Scene s;
  s.name = "slope";
  scene::MapLight spot;
  spot.direction = glm::vec3(1.0f, 0.0f, 0.0f);
  s.map_lights.push_back(spot);
  const glm::dmat4 inverse =
      glm::inverse(glm::dmat4(gpu::map_view_projection(s, spot, 0, cube::DepthRange::zero_to_one)));
  auto at = [&](double x, double y, double depth) {  // texel point and window depth to world
    const glm::dvec4 p = inverse * glm::dvec4(2.0 * x / kSize - 1.0, 2.0 * y / kSize - 1.0, depth, 1.0);
    return glm::vec3(glm::dvec3(p) / p.w);
  };
  for (const glm::vec3& p : {at(edge, 0.0, 0.9), at(edge, 8.0, 0.9), at(8.0, 4.5, 0.5)})
    s.vertices.push_back({p, glm::vec3(-1, 0, 0), glm::vec3(1)});
  scene::Object o;
  o.name = "slope";
  o.vertex_count = 3;
  s.objects.push_back(o);  // not a closed object: nothing culled
  const reference::RayCaster caster(s);
  const MapTruth truth = compute_map_truth(caster, s, 0, kSize, cube::DepthRange::zero_to_one);
  const double reach = raster_reach_texels(kBits);
  ASSERT_LT(truth.cast(0, 4.5, 4.5), 1.0);
  ASSERT_EQ(truth.cast(0, 4.5 - reach, 4.5 - reach), 1.0);
  // The surface at (5, 4.5) extended to a point: its plane there (a square of no reach).
  auto plane_at = [&](double x) { return truth.sample(0, 5.0, 4.5, x, 4.5, 0.0).plane_lo; };
  const double at_edge = plane_at(edge + 1e-6), beyond = plane_at(4.5 - reach - step);
  const double corners_max =
      std::max(truth.cast(0, 4.5 + reach, 4.5 - reach), truth.cast(0, 4.5 + reach, 4.5 + reach));
  EXPECT_GT(at_edge, corners_max + 1e-4) << "the corners alone would not bound it";
  Images images;
  images.map_size = kSize;
  images.map_depth_zero_to_one = true;
  images.map_depth = truth.depth;
  auto bad_with = [&](double stored) {
    images.map_depth[0][4 * kSize + 4] = float(stored);
    return check_map_texels(truth, images, DepthFormat::d32f, kBits).bad();
  };
  EXPECT_EQ(bad_with(truth.depth[0][4 * kSize + 4]), 0u);
  EXPECT_EQ(bad_with(at_edge), 0u);
  EXPECT_EQ(bad_with(beyond), 1u);
}

}  // namespace
}  // namespace omnishadow::bench
