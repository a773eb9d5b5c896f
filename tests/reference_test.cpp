// The ray-cast reference on cases whose answers are known in closed form.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>

#include "backends/reference/ray_caster.h"
#include "bench/truth/accuracy.h"

namespace omnishadow::reference {
namespace {

// Light at (0,5,0) above a ground plane y = 0 (20 x 20) with one occluder.
scene::Scene make_scene(const std::string& occluder) {
  return scene::load_scene_text(R"({"light": {"position": [0, 5, 0], "far": 50}, "objects": [
      {"type": "plane", "scale": [10, 1, 10]}, )" +
                                    occluder + "]}",
                                "test.json");
}

TEST(RayCaster, BoxShadowMatchesItsAnalyticOutline) {
  // Box [-0.5,0.5] x [2,3] x [-0.5,0.5]: its top face (y = 3) projects from the light onto y = 0 scaled by
  // 5 / (5 - 3) = 2.5, so the shadow is the square |x|, |z| <= 1.25 (the bottom face's 5/3 is inside it).
  scene::Scene s = make_scene(R"({"type": "box", "translate": [0, 2.5, 0], "scale": 0.5})");
  RayCaster caster(s);
  const glm::vec3 light(0, 5, 0);
  for (float x = -2.0f; x <= 2.0f; x += 0.05f)
    for (float z : {0.0f, 0.6f, 1.2f, 1.3f, -1.0f}) {
      glm::vec3 p(x, 0, z);
      bool inside = std::fabs(x) < 1.25f && std::fabs(z) < 1.25f;
      bool near_edge = std::fabs(std::fabs(x) - 1.25f) < 1e-3f || std::fabs(std::fabs(z) - 1.25f) < 1e-3f;
      if (near_edge) continue;
      EXPECT_EQ(caster.blocked(light, p, 1e-4f), inside) << "x " << x << " z " << z;
    }
  EXPECT_FALSE(caster.blocked(light, {0, 3.0001f, 0}, 1e-3f)) << "the top face holds itself";
}

// The previous blocker, tried first, changes no answer: over the box's outline (inside, outside, and points
// where the hint's triangle is not the blocker or blocks nothing) every ray answers as without it, and the
// hint ends on a triangle that really blocks.
TEST(RayCaster, LastBlockerHintChangesNoAnswer) {
  scene::Scene s = make_scene(R"({"type": "box", "translate": [0, 2.5, 0], "scale": 0.5}, )"
                              R"({"type": "box", "translate": [3, 2.5, 0], "scale": 0.5})");
  RayCaster caster(s);
  const glm::vec3 light(0, 5, 0);
  uint32_t hint = RayCaster::kNoBlocker;
  int blocked = 0, changes = 0;
  uint32_t previous = hint;
  for (float x = -3.0f; x <= 9.0f; x += 0.037f)
    for (float z : {0.0f, 0.6f, 1.3f, -1.0f}) {
      const glm::vec3 p(x, 0, z);
      const bool plain = caster.blocked(light, p, 1e-4f);
      EXPECT_EQ(caster.blocked(light, p, 1e-4f, &hint), plain) << "x " << x << " z " << z;
      if (plain) {
        ++blocked;
        EXPECT_NE(hint, RayCaster::kNoBlocker);
      }
      changes += hint != previous;
      previous = hint;
    }
  EXPECT_GT(blocked, 20);
  EXPECT_GT(changes, 1) << "the hint moved from one box's triangles to the other's";
  uint32_t junk = 123456789u;  // out of range: ignored, then replaced by a real blocker
  EXPECT_TRUE(caster.blocked(light, {0, 0, 0}, 1e-4f, &junk));
  EXPECT_LT(junk, caster.triangle_count());
}

TEST(RayCaster, SphereShadowIsADiscOfTheAnalyticRadius) {
  // Unit sphere scaled 0.5 at height 2.5: the tangent cone from the light has sin(a) = 0.5 / 2.5, so the
  // shadow on y = 0 (5 below the light) has radius 5 tan(a) = 1.0206. The tessellated sphere is inscribed:
  // its shadow is at most that, and within one segment's sagitta of it.
  scene::Scene s =
      make_scene(R"({"type": "sphere", "segments": [128, 64], "translate": [0, 2.5, 0], "scale": 0.5})");
  RayCaster caster(s);
  const double exact = 5.0 * std::tan(std::asin(0.2));
  for (int k = 0; k < 16; ++k) {
    double angle = 2.0 * 3.14159265358979 * k / 16.0 + 0.1;
    glm::vec3 dir(static_cast<float>(std::cos(angle)), 0, static_cast<float>(std::sin(angle)));
    EXPECT_TRUE(caster.blocked({0, 5, 0}, dir * static_cast<float>(exact * 0.99), 1e-4f)) << angle;
    EXPECT_FALSE(caster.blocked({0, 5, 0}, dir * static_cast<float>(exact * 1.01), 1e-4f)) << angle;
  }
}

TEST(RayCaster, ClosestHitGivesTheSurfaceAndItsShading) {
  scene::Scene s =
      make_scene(R"({"type": "box", "translate": [0, 2.5, 0], "scale": 0.5, "color": [1, 0, 0]})");
  RayCaster caster(s);
  Hit h = caster.closest({0, 10, 0}, {0, -1, 0}, 100.0);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.distance, 7.0, 1e-9);  // the box top at y = 3
  EXPECT_EQ(caster.color_at(h), glm::vec3(1, 0, 0));
  EXPECT_NEAR(caster.normal_at(h).y, 1.0f, 1e-6);
  Hit ground = caster.closest({3, 10, 3}, {0, -1, 0}, 100.0);
  ASSERT_TRUE(ground.hit);
  EXPECT_NEAR(ground.distance, 10.0, 1e-9);
  EXPECT_FALSE(caster.closest({30, 10, 30}, {0, -1, 0}, 100.0).hit);
}

// A row of floor points (y = 0) at these x, as the GPU's world positions of a 9x1 image.
Images floor_row(const std::array<float, 9>& xs) {
  Images img;
  img.width = 9;
  img.height = 1;
  for (float x : xs) img.world_position.insert(img.world_position.end(), {x, 0.0f, 0.0f, 1.0f});
  img.shadow_factor.assign(9, 0.0f);
  return img;
}

TEST(Truth, SphericalLightGivesAPenumbraBetweenUmbraAndLight) {
  // Box shadow edge at x = 1.25 (point light). With a light of radius 0.5 the edge blurs: full shadow well
  // inside, none well outside, a fraction strictly between near the edge, growing monotonically inwards.
  scene::Scene s = make_scene(R"({"type": "box", "translate": [0, 2.5, 0], "scale": 0.5})");
  RayCaster caster(s);
  const std::array<float, 9> xs = {0.0f, 0.6f, 0.9f, 1.1f, 1.25f, 1.4f, 1.6f, 2.0f, 3.0f};
  Images img = floor_row(xs);
  bench::TruthOptions o;
  o.light_radius = 0.5f;
  o.samples_per_axis = 16;
  bench::Truth t = bench::compute_truth(caster, s, 0, img, o);
  EXPECT_EQ(t.sphere_shadow[0], 1.0f);
  EXPECT_EQ(t.sphere_shadow[8], 0.0f);
  EXPECT_GT(t.sphere_shadow[4], 0.2f);
  EXPECT_LT(t.sphere_shadow[4], 0.8f);
  for (int i = 1; i < 9; ++i) EXPECT_LE(t.sphere_shadow[i], t.sphere_shadow[i - 1]) << "x " << xs[i];
  EXPECT_EQ(t.point_shadow[3], 1.0f);
  EXPECT_EQ(t.point_shadow[5], 0.0f);
  // Deterministic: the same request gives the same samples.
  EXPECT_EQ(bench::compute_truth(caster, s, 0, img, o).sphere_shadow, t.sphere_shadow);
}

// A prior truth (another API's) gives its values to pixels on the same surface point and no others: positions
// moved by float rounding (within the GL rule's 1 part in 1e5 per operation) reuse every pixel with the
// answers a fresh cast gives; a position moved by a pixel's footprint is cast again, with its own answer.
TEST(Truth, PriorSharesSameSurfacePixelsAndCastsTheRest) {
  // The penumbra scene above; no point on the point light's edge (x = 1.25), where ulps could change the
  // answer.
  scene::Scene s = make_scene(R"({"type": "box", "translate": [0, 2.5, 0], "scale": 0.5})");
  RayCaster caster(s);
  Images img = floor_row({0.0f, 0.6f, 0.9f, 1.1f, 1.2f, 1.3f, 1.6f, 2.0f, 3.0f});
  bench::TruthOptions o;
  o.light_radius = 0.5f;
  o.samples_per_axis = 4;
  const bench::Truth first = bench::compute_truth(caster, s, 0, img, o);
  EXPECT_EQ(first.reused_pixels, 0u);

  Images rounded = img;  // the other API: every coordinate a few ulps away
  for (size_t i = 0; i < rounded.world_position.size(); i += 4)
    rounded.world_position[i] = std::nextafter(std::nextafter(rounded.world_position[i], 10.0f), 10.0f);
  const bench::Truth shared = bench::compute_truth(caster, s, 0, rounded, o, {&first, &img.world_position});
  const bench::Truth fresh = bench::compute_truth(caster, s, 0, rounded, o);
  EXPECT_EQ(shared.reused_pixels, 9u);
  EXPECT_EQ(shared.point_shadow, fresh.point_shadow);
  EXPECT_EQ(shared.sphere_shadow, fresh.sphere_shadow);

  Images moved = img;  // pixel 3 (x 1.1, hidden) now shows a lit point: another surface point, cast again
  moved.world_position[4 * 3] = 3.0f;
  const bench::Truth recast = bench::compute_truth(caster, s, 0, moved, o, {&first, &img.world_position});
  EXPECT_EQ(recast.reused_pixels, 8u);
  EXPECT_EQ(first.point_shadow[3], 1.0f);
  EXPECT_EQ(recast.point_shadow[3], 0.0f);
  EXPECT_EQ(recast.point_shadow, bench::compute_truth(caster, s, 0, moved, o).point_shadow);

  bench::TruthOptions other = o;  // a prior cast with other options is not used
  other.light_radius = 0.25f;
  EXPECT_EQ(bench::compute_truth(caster, s, 0, rounded, other, {&first, &img.world_position}).reused_pixels,
            0u);
}

TEST(Truth, MetricsCountFalseAndMissedShadowsApart) {
  bench::Truth t;
  t.width = 4;
  t.height = 1;
  t.covered = {1, 1, 1, 0};
  t.point_shadow = {1, 0, 1, 0};
  t.direct.assign(4, glm::vec3(0.5f));
  t.has_direct = {1, 1, 1, 0};
  Images img;
  img.shadow_factor = {1.0f, 1.0f, 0.0f, 1.0f};  // right, false shadow, missed shadow, uncovered
  bench::Accuracy a = bench::measure_accuracy(t, img);
  EXPECT_EQ(a.pixels, 3u);
  EXPECT_NEAR(a.misclassified_percent, 200.0 / 3.0, 1e-9);
  EXPECT_NEAR(a.false_shadow_percent, 100.0 / 3.0, 1e-9);
  EXPECT_NEAR(a.missed_shadow_percent, 100.0 / 3.0, 1e-9);
  EXPECT_NEAR(a.mae_point, 2.0 / 3.0, 1e-9);
  // Two pixels off by 1 in shadow: each changes 3 channels by 0.5 -> MSE = 6 * 0.25 / 9.
  EXPECT_NEAR(a.psnr_point_db, 10.0 * std::log10(9.0 / 1.5), 1e-9);
  img.shadow_factor = {1.0f, 0.0f, 1.0f, 0.0f};
  EXPECT_EQ(bench::measure_accuracy(t, img).psnr_point_db, -1.0) << "identical: no finite PSNR";
}

// The radius fit: a shadow factor equal to one radius's truth picks that radius; the point light's truth
// picks 0.
TEST(Truth, RadiusFitPicksTheLightAFilterImitates) {
  scene::Scene s = make_scene(R"({"type": "box", "translate": [0, 2.5, 0], "scale": 0.5})");
  RayCaster caster(s);
  Images img;
  img.width = 64;  // every kFitStride-th pixel of one row is sampled: 16 pixels across the shadow's edge
  img.height = 1;
  for (int x = 0; x < img.width; ++x)
    img.world_position.insert(img.world_position.end(), {x * 0.05f, 0.0f, 0.0f, 1.0f});
  bench::TruthOptions o;
  o.light_radius = 0.1f;
  bench::Truth t = bench::compute_truth(caster, s, 0, img, o);
  ASSERT_EQ(t.fit_pixels.size(), 16u);
  ASSERT_EQ(t.fit_shadow.size(), bench::kFitRadii.size());
  for (size_t r : {size_t{0}, size_t{5}}) {
    img.shadow_factor.assign(64, 0.0f);
    for (size_t j = 0; j < t.fit_pixels.size(); ++j) img.shadow_factor[t.fit_pixels[j]] = t.fit_shadow[r][j];
    bench::Accuracy a = bench::measure_accuracy(t, img);
    EXPECT_EQ(a.fit_radius, bench::kFitRadii[r]);
    EXPECT_EQ(a.fit_mae_best, 0.0);
    EXPECT_EQ(a.fit_mae.size(), bench::kFitRadii.size());
  }
  o.light_radius = 0.0f;  // no soft reference: no fit either
  EXPECT_TRUE(bench::compute_truth(caster, s, 0, img, o).fit_pixels.empty());
}

// Large frames cast the soft reference at every sphere_stride-th pixel: the stride keeps the rays under the
// budget of an 800x600 frame, and the sphere figures (means) over the subsample stay close to the full
// frame's.
TEST(Truth, SoftReferenceIsSubsampledAboveAnEightHundredBySixHundredFrame) {
  bench::TruthOptions o;
  EXPECT_EQ(bench::sphere_stride_for(o, 800, 600), 1);
  EXPECT_EQ(bench::sphere_stride_for(o, 1920, 1080), 3);
  EXPECT_EQ(bench::sphere_stride_for(o, 3840, 2160), 5);
  o.sphere_stride = 2;
  EXPECT_EQ(bench::sphere_stride_for(o, 800, 600), 2);

  scene::Scene s = make_scene(R"({"type": "box", "translate": [0, 2.5, 0], "scale": 0.5})");
  RayCaster caster(s);
  Images img;
  img.width = 240;  // x from 0 to 2.4 across the penumbra of the box's shadow edge (x = 1.25), two rows
  img.height = 2;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      img.world_position.insert(img.world_position.end(), {x * 0.01f, 0.0f, y * 0.01f, 1.0f});
  o.light_radius = 0.5f;
  o.samples_per_axis = 8;
  o.sphere_stride = 1;
  bench::Truth full = bench::compute_truth(caster, s, 0, img, o);
  o.sphere_stride = 2;
  bench::Truth sub = bench::compute_truth(caster, s, 0, img, o);
  img.shadow_factor = full.point_shadow;  // a hard shadow, judged against the soft light
  bench::Accuracy a = bench::measure_accuracy(full, img), b = bench::measure_accuracy(sub, img);
  EXPECT_EQ(a.sphere_pixels, 480u);
  EXPECT_EQ(b.sphere_pixels, 120u);
  EXPECT_EQ(b.sphere_stride, 2);
  EXPECT_GT(a.mae_sphere, 0.05);
  EXPECT_NEAR(b.mae_sphere, a.mae_sphere, 0.1 * a.mae_sphere);
  EXPECT_EQ(b.misclassified_percent, a.misclassified_percent) << "point figures use every pixel";
}

// Cases share a truth when their positions' fingerprints agree: any changed bit, anywhere, must tell them
// apart.
TEST(Truth, FingerprintTellsPositionBuffersApart) {
  Images a;
  a.width = 7;
  a.height = 3;
  for (int i = 0; i < a.width * a.height * 4; ++i) a.world_position.push_back(0.37f * float(i) - 2.0f);
  Images same = a;
  EXPECT_EQ(bench::positions_fingerprint(a), bench::positions_fingerprint(same));
  for (size_t value : {size_t(0), size_t(41), a.world_position.size() - 1}) {
    for (int bit : {0, 17, 31}) {
      Images b = a;
      uint32_t word;
      std::memcpy(&word, &b.world_position[value], 4);
      word ^= 1u << bit;
      std::memcpy(&b.world_position[value], &word, 4);
      EXPECT_NE(bench::positions_fingerprint(a), bench::positions_fingerprint(b))
          << "value " << value << " bit " << bit;
    }
  }
  Images swapped = a;
  std::swap(swapped.width, swapped.height);
  EXPECT_NE(bench::positions_fingerprint(a), bench::positions_fingerprint(swapped))
      << "the size is part of it";
}

}  // namespace
}  // namespace omnishadow::reference
