// The lookup check (bench/truth/lookup_check.h) on made-up read-backs: a shadow factor the cube-map rule gives
// passes, one it cannot give fails, a tap on a texel boundary allows either texel, and the kernel comes from the
// shader's own table.
#include <gtest/gtest.h>

#include <limits>

#include "bench/truth/lookup_check.h"

namespace omnishadow::bench {
namespace {

// A 4x4 cube around a light at the origin whose every texel stores `distance`; one covered pixel at `position`.
Images one_pixel(const glm::vec3& position, float distance, float shadow) {
  Images img;
  img.width = 1;
  img.height = 1;
  img.world_position = {position.x, position.y, position.z, 1.0f};
  img.shadow_factor = {shadow};
  img.cube_size = 4;
  img.light_far = 100.0f;
  for (auto& face : img.cube_distance) face.assign(16, distance);
  return img;
}

TEST(LookupCheck, AcceptsWhatTheRuleGivesAndRejectsTheRest) {
  LookupInputs in;  // hard, tutorial bias 0.05, light at the origin
  // A surface at distance 10 behind an occluder stored at 6: shadowed (1); lit (0) cannot be read from any texel.
  EXPECT_TRUE(check_lookups(one_pixel({10, 1, 2}, 6.0f, 1.0f), in).ok());
  LookupReport wrong = check_lookups(one_pixel({10, 1, 2}, 6.0f, 0.0f), in);
  EXPECT_EQ(wrong.outside, 1u);
  EXPECT_NE(describe(wrong).find("1 of 1 pixels"), std::string::npos) << describe(wrong);
  // The surface itself stored: lit by the bias.
  const float d = glm::length(glm::vec3(10, 1, 2));
  EXPECT_TRUE(check_lookups(one_pixel({10, 1, 2}, d, 0.0f), in).ok());
  EXPECT_FALSE(check_lookups(one_pixel({10, 1, 2}, d, 1.0f), in).ok());
  // Without the bias the comparison is within rounding: both outcomes are allowed.
  in.bias = BiasMode::zero;
  EXPECT_TRUE(check_lookups(one_pixel({10, 1, 2}, d, 0.0f), in).ok());
  EXPECT_TRUE(check_lookups(one_pixel({10, 1, 2}, d, 1.0f), in).ok());
}

TEST(LookupCheck, ATapOnATexelBoundaryMayReadEitherTexel) {
  LookupInputs in;
  // Direction (10, 0, 0.0001) on +X: s = (-z/x + 1) * 2 = 1.99998 texels, within 1/16 of the boundary at 2.
  Images img = one_pixel({10, 0.0f, 0.0001f}, 20.0f, 1.0f);
  // +X face, t = 2 (y = 0 maps to t = 2 of 4), s = 1 occludes; s = 2 does not.
  img.cube_distance[0][2 * 4 + 1] = 5.0f;
  EXPECT_TRUE(check_lookups(img, in).ok());
  img.shadow_factor = {0.0f};
  EXPECT_TRUE(check_lookups(img, in).ok());
  // Away from the boundaries (s = 1.5, t = 2.5) only texel (1, 2) is allowed.
  img = one_pixel({10, -2.5f, 2.5f}, 20.0f, 0.0f);
  img.cube_distance[0][2 * 4 + 1] = 5.0f;
  EXPECT_FALSE(check_lookups(img, in).ok());
  // With 8 sub-texel bits the band around a boundary narrows: s = 2 - 1/32 reads texel 1 only.
  in.subtexel_bits = 8;
  img = one_pixel({10, -2.5f, 10.0f / 64.0f}, 20.0f, 0.0f);
  img.cube_distance[0][2 * 4 + 1] = 5.0f;
  EXPECT_FALSE(check_lookups(img, in).ok());
  in.subtexel_bits = 4;
  EXPECT_TRUE(check_lookups(img, in).ok());
}

TEST(LookupCheck, KernelsAreTheShadersOwn) {
  const auto& disk = disk_directions();
  ASSERT_EQ(disk.size(), 20u);
  EXPECT_EQ(disk[0], glm::dvec3(1, 1, 1));
  EXPECT_EQ(disk[19], glm::dvec3(0, 1, -1));
  // pcf_disk20 over a cube whose texels all occlude: shadow 1; half the taps cannot be lit.
  LookupInputs in;
  in.filter = Filter::pcf_disk20;
  in.camera = {0, 0, 30};
  EXPECT_TRUE(check_lookups(one_pixel({10, 1, 2}, 6.0f, 1.0f), in).ok());
  EXPECT_FALSE(check_lookups(one_pixel({10, 1, 2}, 6.0f, 0.5f), in).ok());
  in.filter = Filter::pcf_grid64;
  EXPECT_TRUE(check_lookups(one_pixel({10, 1, 2}, 30.0f, 0.0f), in).ok());
  EXPECT_FALSE(check_lookups(one_pixel({10, 1, 2}, 30.0f, 1.0f / 64.0f), in).ok());
}

// A read-back the check cannot make sense of (no far plane, positions at the light, non-finite values) allows
// any texel rather than reading outside the cube.
TEST(LookupCheck, DegenerateInputsAllowAnyTexel) {
  LookupInputs in;
  in.filter = Filter::pcf_disk20;
  in.far_plane = 0.0;  // the radius divides by it
  in.camera = {10, 1, 2};  // at the pixel: 0 / 0
  EXPECT_TRUE(check_lookups(one_pixel({10, 1, 2}, 6.0f, 0.25f), in).ok());
  in.filter = Filter::hard;
  in.far_plane = 100.0;
  EXPECT_TRUE(check_lookups(one_pixel({0, 0, 0}, 6.0f, 1.0f), in).ok()) << "the pixel at the light";
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(check_lookups(one_pixel({10, nan, 2}, 6.0f, 1.0f), in).ok());
  EXPECT_FALSE(check_lookups(one_pixel({10, 1, 2}, 6.0f, nan), in).ok()) << "a NaN shadow factor is no value";
}

TEST(LookupCheck, SaysWhyItDoesNotApply) {
  CaseConfig c;
  Images img = one_pixel({10, 1, 2}, 6.0f, 1.0f);
  EXPECT_EQ(lookup_check_skip_reason(c, img, true), "");
  EXPECT_EQ(lookup_check_skip_reason(c, img, false), "no point light");
  c.filter = Filter::vsm;
  EXPECT_NE(lookup_check_skip_reason(c, img, true).find("vsm"), std::string::npos);
  c.filter = Filter::hard;
  c.remedies.bias = BiasMode::slope;
  EXPECT_NE(lookup_check_skip_reason(c, img, true).find("normal"), std::string::npos);
  c.remedies.bias = BiasMode::tutorial;
  for (auto& face : img.cube_distance) face.clear();
  EXPECT_NE(lookup_check_skip_reason(c, img, true).find("in full"), std::string::npos);
}

}  // namespace
}  // namespace omnishadow::bench
