// Dual-paraboloid conventions (backends/common/paraboloid.h): the map and its inverse agree, every direction
// has one layer, the equator is the unit circle, and each layer keeps a triangle's winding as the cube face
// looking the same way does (so the shadow pass culls the same faces in every layout).
#include "backends/common/paraboloid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "backends/common/cube_faces.h"

namespace omnishadow::paraboloid {
namespace {

TEST(Paraboloid, DirectionsRoundTripThroughTheirLayer) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n;
  for (int i = 0; i < 10000; ++i) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(n(rng), n(rng), n(rng)));
    const LayerCoord c = direction_to_layer(d);
    EXPECT_EQ(c.layer, d.z >= 0 ? 0 : 1);
    EXPECT_LE(c.x * c.x + c.y * c.y, 1.0 + 1e-12) << "inside the unit disk";
    const glm::dvec3 back = layer_point_direction(c.layer, c.x, c.y);
    EXPECT_NEAR(glm::length(back - d), 0.0, 1e-12);
  }
}

TEST(Paraboloid, AxesAndEquatorLandWhereTheConventionSays) {
  auto at = [](glm::dvec3 d) { return direction_to_layer(d); };
  EXPECT_EQ(at({0, 0, 1}).layer, 0);
  EXPECT_EQ(at({0, 0, -1}).layer, 1);
  EXPECT_NEAR(at({0, 0, 1}).x, 0.0, 1e-15);
  EXPECT_NEAR(at({0, 0, -1}).y, 0.0, 1e-15);
  // Layer 0 looks along +Z with +Y up: world +X is window -x. Layer 1 looks along -Z: world +X is window +x.
  EXPECT_NEAR(at({1, 0, 1e-9}).x, -1.0, 1e-8);
  EXPECT_NEAR(at({1, 0, -1e-9}).x, 1.0, 1e-8);
  EXPECT_NEAR(at({0, 1, 1e-9}).y, 1.0, 1e-8);
  EXPECT_EQ(at({1, 0, 0}).layer, 0) << "the equator belongs to layer 0";
  for (double angle = 0; angle < 6.28; angle += 0.1) {
    const LayerCoord c = at({std::cos(angle), std::sin(angle), 0.0});
    EXPECT_NEAR(c.x * c.x + c.y * c.y, 1.0, 1e-12) << "the equator is the unit circle";
  }
}

// The sign of the map's Jacobian (window x, y against the direction's two tangent components) is the cube
// face's along the same axis: +Z (face 4) for layer 0, -Z (face 5) for layer 1.
TEST(Paraboloid, LayersKeepTheWindingOfTheCubeFaceAlongTheirAxis) {
  for (int layer = 0; layer < 2; ++layer) {
    const double a = layer == 0 ? 1.0 : -1.0;
    const double h = 1e-4;
    auto p = [&](double u, double v) { return direction_to_layer({u, v, a}); };
    const double jx_u = (p(h, 0).x - p(-h, 0).x) / (2 * h), jx_v = (p(0, h).x - p(0, -h).x) / (2 * h);
    const double jy_u = (p(h, 0).y - p(-h, 0).y) / (2 * h), jy_v = (p(0, h).y - p(0, -h).y) / (2 * h);
    auto f = [&](float u, float v) { return cube::direction_to_face({u, v, static_cast<float>(a)}); };
    const float k = 1e-2f;
    const double cs_u = (f(k, 0).s - f(-k, 0).s) / (2 * k), cs_v = (f(0, k).s - f(0, -k).s) / (2 * k);
    const double ct_u = (f(k, 0).t - f(-k, 0).t) / (2 * k), ct_v = (f(0, k).t - f(0, -k).t) / (2 * k);
    EXPECT_EQ(std::signbit(jx_u * jy_v - jx_v * jy_u), std::signbit(cs_u * ct_v - cs_v * ct_u))
        << "layer " << layer;
  }
}

TEST(Paraboloid, TexelsMapToTheirCentresAndTheDiskHoldsTheLookups) {
  const int size = 64;
  int inside = 0;
  for (int t = 0; t < size; ++t)
    for (int s = 0; s < size; ++s) {
      if (!texel_in_disk(s, t, size)) continue;
      ++inside;
      for (int layer = 0; layer < 2; ++layer) {
        const LayerCoord c = direction_to_layer(texel_point_direction(layer, s + 0.5, t + 0.5, size));
        EXPECT_EQ(c.layer, layer);
        EXPECT_EQ(static_cast<int>(std::floor((c.x + 1.0) * 0.5 * size)), s);
        EXPECT_EQ(static_cast<int>(std::floor((c.y + 1.0) * 0.5 * size)), t);
      }
    }
  EXPECT_NEAR(static_cast<double>(inside) / (size * size), 3.14159265 / 4, 0.01)
      << "pi/4 of a layer is the disk";
  EXPECT_EQ(layer_size_for_cube(512), 887) << "2 x 887^2 = 1.574 M texels, a 512 cube's 6 x 512^2 = 1.573 M";
}

}  // namespace
}  // namespace omnishadow::paraboloid
