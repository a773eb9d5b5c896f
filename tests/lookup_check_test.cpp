// The lookup check (bench/truth/lookup_check.h) on made-up read-backs: a shadow factor the cube-map rule
// gives passes, one it cannot give fails, a tap on a texel boundary allows either texel, and the kernel comes
// from the shader's own table.
#include "bench/truth/lookup_check.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace omnishadow::bench {
namespace {

// A 4x4 cube around a light at the origin whose every texel stores `distance`; one covered pixel at
// `position`.
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
  // A surface at distance 10 behind an occluder stored at 6: shadowed (1); lit (0) cannot be read from any
  // texel.
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

// A point beyond the light's far plane is out of its range: the lighting pass reports 0 there whatever the
// taps read (lighting.frag), and within float rounding of the far plane either value.
TEST(LookupCheck, BeyondTheLightsRangeTheFactorIsZero) {
  LookupInputs in;
  Images beyond = one_pixel({10, 1, 2}, 6.0f, 0.0f);  // occluded at 6, but 10.2 units away
  beyond.light_far = 9.0f;
  EXPECT_TRUE(check_lookups(beyond, in).ok());
  beyond.shadow_factor = {1.0f};
  EXPECT_FALSE(check_lookups(beyond, in).ok()) << "what the taps give, reported beyond the range";
  const double d = glm::length(glm::dvec3(10, 1, 2));
  beyond.light_far = float(d);
  for (float shadow : {0.0f, 1.0f}) {
    beyond.shadow_factor = {shadow};
    EXPECT_TRUE(check_lookups(beyond, in).ok()) << "at the range, shadow " << shadow;
  }
  beyond.light_far = float(d * (1.0 + 1e-5));
  beyond.shadow_factor = {0.0f};
  EXPECT_FALSE(check_lookups(beyond, in).ok()) << "within the range the occluder at 6 shadows";
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

// Every tap of each kernel counts: a cube fine enough that the taps read different texels (1024: 0.02 world
// units a texel at distance 10 on +X, against the grid's 0.05 step and the disk's 0.5 radius), lit everywhere
// but the one texel tap k reads (the kernel as the tutorial writes it: the grid -0.1 + 0.05 i per axis, the
// disk's 20 directions times (1 + view distance / far) / 25), which occludes. The device would return (taps
// on that texel) / (taps); the check must allow that value for every k and refuse 0. A kernel with other
// offsets, another count or another scale in the check fails here.
struct KernelProbe {
  Images img;
  std::vector<glm::dvec3> taps;  // light-to-tap vectors, the shader's way
};

int texel_on_pos_x(const glm::dvec3& d, int size) {  // +X: s from -z / x, t from -y / x (cube_faces.h)
  const int s = int(std::floor(0.5 * (-d.z / d.x + 1.0) * size)),
            t = int(std::floor(0.5 * (-d.y / d.x + 1.0) * size));
  return t * size + s;
}

void expect_every_tap_counts(KernelProbe& probe, const LookupInputs& in, const char* name) {
  const int size = probe.img.cube_size;
  std::vector<int> texel(probe.taps.size());
  for (size_t k = 0; k < probe.taps.size(); ++k) {
    ASSERT_GT(probe.taps[k].x, std::max(std::abs(probe.taps[k].y), std::abs(probe.taps[k].z))) << "tap on +X";
    texel[k] = texel_on_pos_x(probe.taps[k], size);
  }
  int refused_zero = 0;
  for (size_t k = 0; k < probe.taps.size(); ++k) {
    probe.img.cube_distance[0][size_t(texel[k])] = 5.0f;  // an occluder in front of the surface at ~10
    const int on_texel = int(std::count(texel.begin(), texel.end(), texel[k]));
    probe.img.shadow_factor = {float(on_texel) / float(probe.taps.size())};
    EXPECT_TRUE(check_lookups(probe.img, in).ok())
        << name << " tap " << k << ": " << describe(check_lookups(probe.img, in));
    probe.img.shadow_factor = {0.0f};
    refused_zero += !check_lookups(probe.img, in).ok();
    probe.img.cube_distance[0][size_t(texel[k])] = 20.0f;
  }
  // A tap within the sub-texel band of a texel edge may read its neighbour instead: such taps allow 0 too.
  EXPECT_GE(refused_zero, int(probe.taps.size()) * 3 / 4) << name << ": the occluding texel must count";
}

TEST(LookupCheck, EveryTapOfEachKernelCounts) {
  const glm::dvec3 p(10.0, 0.3, 0.7);
  KernelProbe probe;
  probe.img = one_pixel(glm::vec3(p), 20.0f, 0.0f);
  probe.img.cube_size = 1024;
  for (auto& face : probe.img.cube_distance) face.assign(size_t(1024) * 1024, 20.0f);
  LookupInputs in;
  in.subtexel_bits = 8;
  in.filter = Filter::pcf_grid64;
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y)
      for (int z = 0; z < 4; ++z) probe.taps.push_back(p + glm::dvec3(-0.1) + 0.05 * glm::dvec3(x, y, z));
  expect_every_tap_counts(probe, in, "pcf_grid64");

  const auto& disk = disk_directions();
  ASSERT_EQ(disk.size(), 20u);
  EXPECT_EQ(disk[0], glm::dvec3(1, 1, 1));
  EXPECT_EQ(disk[19], glm::dvec3(0, 1, -1));
  in.filter = Filter::pcf_disk20;
  in.camera = {0, 0, 30};
  in.far_plane = probe.img.light_far;
  const double radius = (1.0 + glm::length(in.camera - p) / in.far_plane) / 25.0;
  probe.taps.clear();
  for (const glm::dvec3& d : disk) probe.taps.push_back(p + radius * d);
  expect_every_tap_counts(probe, in, "pcf_disk20");
}

// A read-back the check cannot make sense of (no far plane, positions at the light, non-finite values) allows
// any texel rather than reading outside the cube.
TEST(LookupCheck, DegenerateInputsAllowAnyTexel) {
  LookupInputs in;
  in.filter = Filter::pcf_disk20;
  in.far_plane = 0.0;      // the radius divides by it
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
