// The checks' tolerances on every backend, proved both ways: a perturbation within what the API guarantees
// (sub-pixel rasterisation, sub-texel lookups, rounding of the timed lighting) passes, one beyond it fails;
// and the error falls as the cube grows.

#include <gtest/gtest.h>

#include <cstdio>
#include <optional>
#include <vector>

#include "bench/truth/accuracy.h"
#include "bench/truth/case_checks.h"
#include "bench/truth/cube_truth.h"
#include "bench/truth/lookup_check.h"
#include "tests/backend_fixture.h"

namespace omnishadow {
namespace {

// The texel bound from the rasterisation rules (bench/truth/texel_bounds.h), both sides. A conformant GPU
// snaps vertices differently from llvmpipe/lavapipe (an H100 failed 0.175% of room's texels at cube 64 under
// a centre-only bound); --raster-perturb moves every vertex by up to one sub-pixel step to play such a device
// here. The perturbed cube passes the device's bound and fails a bound without sub-pixel reach (the old one),
// and planted bugs still fail with the reach.
TEST_P(BackendTest, PerturbedRasterPassesTheSubPixelBoundOnly) {
  const int bits = backend_->device().subpixel_bits;
  ASSERT_GE(bits, 4) << "both APIs require at least 4 sub-pixel bits";
  reference::RayCaster caster(*room_);
  const glm::vec3 light = room_->light().path.at(0);
  for (Technique t : {Technique::six_pass, Technique::geometry_shader}) {
    CaseConfig c = room_case(t, Filter::hard, 64);
    c.raster_perturb_steps = 1.0f;
    Images img = render(c, 0);
    bench::CubeTruth truth =
        bench::compute_cube_truth(caster, *room_, light, room_->light().near_plane, img.light_far, 64, false);
    bench::CubeTexelReport ok = bench::check_cube_texels(truth, img, Storage::linear_depth, DepthFormat::d32f,
                                                         room_->light().near_plane, bits);
    EXPECT_LE(ok.bad_percent(), bench::kCubeTexelLimitPercent) << to_string(t) << ": " << bench::describe(ok);
    bench::CubeTexelReport centre_only = bench::check_cube_texels(
        truth, img, Storage::linear_depth, DepthFormat::d32f, room_->light().near_plane, 60);
    EXPECT_GT(centre_only.bad_percent(), bench::kCubeTexelLimitPercent)
        << to_string(t) << ": the perturbation no longer moves silhouettes: " << bench::describe(centre_only);
    std::printf("%s: sub-pixel bound %.3g%% wrong, centre-only %.3g%% (%s)\n",
                std::string(to_string(t)).c_str(), ok.bad_percent(), centre_only.bad_percent(),
                bench::describe(centre_only).c_str());
    ASSERT_FALSE(centre_only.worst.empty());
    EXPECT_GE(centre_only.worst.front().edge_texels, 0.0)
        << "a texel the perturbation flipped lies at a depth edge";
    Images swapped = img;
    std::swap(swapped.cube_distance[0], swapped.cube_distance[1]);  // +X and -X
    EXPECT_GT(bench::check_cube_texels(truth, swapped, Storage::linear_depth, DepthFormat::d32f,
                                       room_->light().near_plane, bits)
                  .bad_percent(),
              5.0);
  }
}

// The lookup check's bound (bench/truth/lookup_check.h), both sides: lookups moved by 0.8 of the sampler's
// sub-texel step (the device's subTexelPrecisionBits; 4 assumed for GL) along both face axes, as a coarser
// sampler may read, pass on both layouts; moved by half a texel, or replayed against a cube whose +Y and -Y
// faces are swapped (what a face_array lookup that reads the wrong layer sees), they fail.
TEST_P(BackendTest, PerturbedLookupsPassTheSubTexelBoundOnly) {
  const int bits = backend_->device().subtexel_bits;
  ASSERT_GE(bits, 4) << "Vulkan requires at least 4 sub-texel bits";
  bench::LookupInputs in;
  in.light = glm::dvec3(room_->light().path.at(0));
  in.camera = glm::dvec3(room_->camera.position);
  in.subtexel_bits = bits;
  for (Layout layout : {Layout::cube, Layout::face_array})
    for (Filter f : {Filter::hard, Filter::pcf_disk20}) {
      CaseConfig c = room_case(Technique::six_pass, f, 256);
      c.layout = layout;
      in.filter = f;
      const std::string what = std::string(to_string(layout)) + "/" + std::string(to_string(f));
      c.lookup_perturb_texels = 0.8f * std::ldexp(1.0f, -bits);
      Images within = render(c, 0);
      in.far_plane = within.light_far;
      bench::LookupReport ok = bench::check_lookups(within, in);
      EXPECT_TRUE(ok.ok()) << what << ": " << bench::describe(ok);
      EXPECT_GT(ok.pixels, 100000u) << what;
      c.lookup_perturb_texels = 0.5f;
      bench::LookupReport half = bench::check_lookups(render(c, 0), in);
      EXPECT_GT(half.outside, 0u) << what << ": half a texel off went unseen";
      c.lookup_perturb_texels = 0.0f;
      Images swapped = render(c, 0);
      std::swap(swapped.cube_distance[2], swapped.cube_distance[3]);
      EXPECT_GT(bench::check_lookups(swapped, in).outside, 0u) << what << ": +Y and -Y swapped went unseen";
    }
}

// timed_lit's tolerance (bench/run/case_runner.h kTimedLitMaxPercent), both sides: a compiler's float
// contraction (0.1% of values one level off) passes; a timed variant that renders another filter, no bias or
// another light count fails.
TEST_P(BackendTest, TimedLitToleranceAllowsRoundingFlipsOnly) {
  CaseConfig c = room_case(Technique::six_pass, Filter::pcf_disk20, 256);
  Images img = render(c, 30);
  auto agrees = [&](const std::vector<uint8_t>& timed, const std::vector<uint8_t>& checked) {
    return bench::timed_variant_check(timed, checked).passed;
  };
  EXPECT_TRUE(agrees(img.timed_lit_rgba8, img.lit_rgba8));
  std::vector<uint8_t> contracted = img.lit_rgba8;
  for (size_t i = 0; i < contracted.size(); i += 1000)
    contracted[i] = contracted[i] == 255 ? 254 : contracted[i] + 1;
  EXPECT_TRUE(agrees(contracted, img.lit_rgba8)) << "0.1% of values one level off is within the guarantee";
  std::vector<uint8_t> two_levels = img.lit_rgba8;
  two_levels[two_levels.size() / 2] = two_levels[two_levels.size() / 2] < 128
                                          ? two_levels[two_levels.size() / 2] + 2
                                          : two_levels[two_levels.size() / 2] - 2;
  EXPECT_FALSE(agrees(two_levels, img.lit_rgba8)) << "a value two levels off is no rounding flip";
  CaseConfig hard = c;
  hard.filter = Filter::hard;
  EXPECT_FALSE(agrees(render(hard, 30).lit_rgba8, img.lit_rgba8)) << "another filter";
  CaseConfig no_bias = c;
  no_bias.remedies.bias = BiasMode::zero;
  EXPECT_FALSE(agrees(render(no_bias, 30).lit_rgba8, img.lit_rgba8)) << "no bias";
  scene::Scene mixed = scene::load_scene_file(kScenes + "/mixed.json");
  backend_->load(mixed);
  CaseConfig m = testing::optimization_case(GetParam(), "mixed", Technique::six_pass);
  Images all = testing::render_frame(*backend_, m, 30);
  mixed.map_lights.pop_back();
  backend_->load(mixed);
  EXPECT_FALSE(agrees(testing::render_frame(*backend_, m, 30).lit_rgba8, all.lit_rgba8)) << "one light fewer";
}

// Error falls as the cube grows: each size's misclassification is at most the previous one's plus a noise
// band of 5% + 0.005 points, and 2048 is at least 3x better than 128. Frame 90 puts the light off-centre.
TEST_P(BackendTest, ErrorFallsAsTheCubeGrows) {
  std::optional<bench::Truth> truth;
  std::vector<double> errors;
  for (int size : {128, 256, 512, 1024, 2048}) {
    Images img = render(room_case(Technique::six_pass, Filter::hard, size), 90);
    if (!truth) truth = point_truth(img, 90);
    errors.push_back(bench::measure_accuracy(*truth, img).misclassified_percent);
  }
  for (size_t i = 1; i < errors.size(); ++i)
    EXPECT_LE(errors[i], errors[i - 1] * 1.05 + 0.005)
        << "cube " << (128 << i) << ": " << errors[i] << "% vs " << errors[i - 1] << "%";
  EXPECT_LT(errors.back() * 3.0, errors.front());
}

}  // namespace
}  // namespace omnishadow
