// A many-light case's findings: which lights its checks read, how each light's findings join the case's, and
// the accuracy pooled over them.

#include <gtest/gtest.h>

#include <cmath>

#include "bench/report/results_writer.h"
#include "bench/truth/findings.h"

namespace omnishadow::bench {
namespace {

TEST(LightFindings, CheckedLightsSpreadOverEveryLightWithAStatedStride) {
  EXPECT_EQ(checked_lights(1), std::vector<int>({0}));
  EXPECT_EQ(checked_lights(4), std::vector<int>({0, 1, 2, 3}));
  EXPECT_EQ(checked_lights(5), std::vector<int>({0, 2, 4}));
  EXPECT_EQ(checked_lights(16), std::vector<int>({0, 4, 8, 12}));
  EXPECT_EQ(checked_lights(64), std::vector<int>({0, 16, 32, 48}));
  EXPECT_EQ(checked_light_stride(64), 16);
  EXPECT_EQ(checked_light_stride(3), 1);
  for (int k = 1; k <= 1024; ++k) {
    const std::vector<int> lights = checked_lights(k);
    EXPECT_LE(int(lights.size()), kCheckedLights) << k;
    EXPECT_EQ(lights.front(), 0);
    EXPECT_LT(lights.back(), k);
  }
}

TEST(LightFindings, ALightsFindingsJoinTheCaseUnderItsName) {
  CaseFindings c;
  c.add({Status::failed_quality, "max_error", "shadow disagrees", {}});
  CaseFindings light;
  light.add({Status::failed_check, "cube_texels", "3 texels wrong", {}});
  light.checks.push_back({"cube_faces", "six_pass", {}, 0.0, 0.0, -1.0, false, "", "values"});
  Accuracy a;
  a.pixels = 10;
  light.accuracy = a;
  merge_light_findings(c, 2, std::move(light));
  EXPECT_EQ(c.status, Status::failed_check) << "the worse status wins";
  EXPECT_EQ(c.reason, "shadow disagrees; light 2: 3 texels wrong");
  ASSERT_EQ(c.checks.size(), 1u);
  EXPECT_EQ(c.checks[0].name, "cube_faces@l2");
  ASSERT_EQ(c.per_light.size(), 1u);
  EXPECT_EQ(c.per_light[0].light, 2);
  EXPECT_EQ(c.per_light[0].accuracy->pixels, 10u);
}

// results.json names a checked light's wrong texels as a one-light case's cube_texels does (its finding reads
// "light 12: ..." with the worst one only): which faces, which texels, what they held and what was exact.
TEST(LightFindings, ResultsNameALightsWrongTexels) {
  CaseResult r;
  r.config.light_count = 24;
  CubeTexelReport clean, wrong;
  clean.texels = wrong.texels = 1536;
  wrong.wrong = 7;
  wrong.max_error = 0.0168;
  wrong.bad_per_face[4] = 7;
  wrong.worst = {{4, 13, 12, 11.095, 11.0896, 0.0156}};
  r.per_light = {{0, std::nullopt, clean, {}}, {12, std::nullopt, wrong, {}}};
  const nlohmann::json lights = case_to_json(r)["accuracy"]["per_light"]["lights"];
  ASSERT_EQ(lights.size(), 2u);
  EXPECT_EQ(lights[0]["cube_texels"], nlohmann::json({{"texels", 1536}, {"bad", 0}}))
      << "a clean light: counts";
  const nlohmann::json& t = lights[1]["cube_texels"];
  EXPECT_EQ(t["bad"], 7);
  EXPECT_EQ(t["wrong"], 7);
  EXPECT_EQ(t["bad_per_face"][4], 7);
  EXPECT_DOUBLE_EQ(t["max_error"].get<double>(), 0.0168);
  ASSERT_EQ(t["worst"].size(), 1u);
  EXPECT_EQ(t["worst"][0]["layer"], 4);
  EXPECT_EQ(t["worst"][0]["s"], 13);
  EXPECT_DOUBLE_EQ(t["worst"][0]["got"].get<double>(), 11.095);
}

TEST(LightFindings, PooledAccuracyWeighsEveryLightsPixels) {
  Accuracy a, b;
  a.pixels = 100;
  a.misclassified_percent = 10.0;
  a.mae_point = 0.2;
  a.psnr_point_db = 20.0;  // mean squared error 0.01
  b.pixels = 300;
  b.misclassified_percent = 2.0;
  b.mae_point = 0.0;
  b.psnr_point_db = -1.0;  // identical: no error
  const Accuracy p = *pooled_accuracy({{0, a, {}, {}}, {4, b, {}, {}}});
  EXPECT_EQ(p.pixels, 400u);
  EXPECT_DOUBLE_EQ(p.misclassified_percent, 4.0);
  EXPECT_DOUBLE_EQ(p.mae_point, 0.05);
  EXPECT_NEAR(p.psnr_point_db, 10.0 * std::log10(400.0 / (0.01 * 100.0)), 1e-9);
  b.psnr_point_db = -1.0;
  a.psnr_point_db = -1.0;
  EXPECT_EQ(pooled_accuracy({{0, a, {}, {}}, {4, b, {}, {}}})->psnr_point_db, -1.0) << "identical stays so";
  EXPECT_FALSE(pooled_accuracy({}).has_value());
  EXPECT_FALSE(pooled_accuracy({{0, std::nullopt, {}, {}}, {4, std::nullopt, {}, {}}}).has_value())
      << "lights whose accuracy was not measured (--no-accuracy) pool to none, not to 0% misclassified";
}

// The lit frame from every light: each light's shadow error weighs its own unshadowed light, and errors of
// opposite sign cancel in the colour (as they do on screen) where pooling per light would add them.
TEST(LightFindings, TheLitFrameOfEveryLightSumsTheirErrorsInColour) {
  auto light = [](float gpu, float exact) {
    Truth t;
    t.covered = {1, 0};
    t.point_shadow = {exact, 0.0f};
    t.direct = {glm::vec3(0.1f), glm::vec3(0.0f)};
    t.has_direct = {1, 0};
    Images img;
    img.shadow_factor = {gpu, 0.0f};
    return std::make_pair(t, img);
  };
  const auto over = light(1.0f, 0.0f), under = light(0.0f, 1.0f), right = light(0.5f, 0.5f);
  auto psnr = [](std::vector<const std::pair<Truth, Images>*> lights) {
    std::vector<std::pair<const Truth*, const Images*>> pairs;
    for (const auto* l : lights) pairs.emplace_back(&l->first, &l->second);
    return lit_psnr_of_lights(pairs);
  };
  EXPECT_NEAR(psnr({&over}), 20.0, 1e-5) << "0.1 off in every channel: mean squared error 0.01";
  EXPECT_NEAR(psnr({&over, &over}), 10.0 * std::log10(1.0 / 0.04), 1e-5) << "two lights' errors add";
  EXPECT_EQ(psnr({&over, &under}), -1.0) << "opposite errors cancel in the lit colour";
  EXPECT_EQ(psnr({&right, &right}), -1.0);
  EXPECT_EQ(psnr({}), -1.0);
}

}  // namespace
}  // namespace omnishadow::bench
