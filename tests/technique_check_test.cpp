// The technique check (check_against_reference: a technique's cube faces against six_pass's) where coverage
// may flip at triangle edges: texels that differ pass while each value is one a rasteriser may store there
// (the texel rule, here a stand-in) and they are few; one value no rasteriser may store fails the case, as
// does a cube that differs everywhere. On made-up read-backs, so no driver is needed.
#include <gtest/gtest.h>

#include "backends/common/cube_summary.h"
#include "bench/truth/case_checks.h"

namespace omnishadow::bench {
namespace {

constexpr int kEdge = 64;  // a layer's edge in texels: 4 layers of 4096

// Six_pass's read-back of a tetrahedral case: every texel at 10 units, far at 100; a lit frame of one pixel.
Images tetrahedral_cube() {
  Images img;
  img.width = 1;
  img.height = 1;
  img.shadow_factor = {0.0f};
  img.lit_rgba8 = {0, 0, 0, 255};
  img.cube_size = kEdge;
  img.light_far = 100.0f;
  for (int f = 0; f < 4; ++f) img.cube_distance[size_t(f)].assign(size_t(kEdge) * kEdge, 10.0f);
  return img;
}

struct Judged {
  CaseFindings findings;
  const CheckResult* faces() const {
    for (const CheckResult& c : findings.checks)
      if (c.name == "cube_faces") return &c;
    return nullptr;
  }
};

// geometry_shader's images held to six_pass's, the texel rule admitting every value but `refused`.
Judged judge(Images images, Images six_pass, float refused) {
  static const scene::Scene scene = [] {
    scene::Scene s;
    s.point_lights.resize(1);
    s.point_lights[0].near_plane = 0.1f;
    return s;
  }();
  static const DeviceInfo device;
  static const CheckOptions options;
  cube::summarize_on_host(
      images);  // the face hashes, as a read-back has them: equal hashes skip the comparison
  cube::summarize_on_host(six_pass);
  Judged j;
  j.findings.config.layout = Layout::tetrahedral;
  j.findings.config.technique = Technique::geometry_shader;
  check_against_reference(j.findings, images, six_pass, CheckContext{scene, device, options, {}},
                          [refused](int, int, int, double d) { return float(d) != refused; });
  return j;
}

TEST(TechniqueCheck, TexelsACoverageFlipMayStoreDifferInFewPlacesOnly) {
  const Images six_pass = tetrahedral_cube();
  Images flipped = six_pass;
  flipped.cube_distance[1][size_t(7) * kEdge + 9] = 42.0f;  // the surface beside an edge: admissible
  Judged ok = judge(flipped, six_pass, -1.0f);
  ASSERT_NE(ok.faces(), nullptr);
  EXPECT_TRUE(ok.faces()->passed);
  EXPECT_EQ(ok.faces()->difference.differing, 1u);
  EXPECT_EQ(ok.faces()->inadmissible, 0u);
  EXPECT_EQ(ok.findings.status, Status::ok) << ok.findings.reason;

  // The same texel holding a value the rule refuses: the case fails, and says so.
  Judged wrong = judge(flipped, six_pass, 42.0f);
  EXPECT_FALSE(wrong.faces()->passed);
  EXPECT_EQ(wrong.faces()->inadmissible, 1u);
  EXPECT_EQ(wrong.findings.status, Status::failed_check);
  EXPECT_NE(wrong.findings.reason.find("1 of them hold a value no rasteriser may store there"),
            std::string::npos)
      << wrong.findings.reason;

  // Admissible everywhere but in more than cross_max_percent of the texels (a shifted map): fails.
  Images shifted = six_pass;
  for (int f = 0; f < 4; ++f)
    for (int t = 0; t < kEdge; t += 8) shifted.cube_distance[size_t(f)][size_t(t) * kEdge] = 11.0f;
  Judged many = judge(shifted, six_pass, -1.0f);
  EXPECT_GT(many.faces()->difference.percent_differing(), CheckOptions{}.cross_max_percent);
  EXPECT_FALSE(many.faces()->passed);
  EXPECT_EQ(many.findings.status, Status::failed_check);
}

// Without a texel rule (a cube whose coverage cannot flip, or no truth): any difference beyond the tolerance
// fails, as before such flips were judged.
TEST(TechniqueCheck, WithoutATexelRuleEveryDifferenceFails) {
  const Images six_pass = tetrahedral_cube();
  Images flipped = six_pass;
  flipped.cube_distance[1][size_t(7) * kEdge + 9] = 42.0f;
  static const scene::Scene scene = [] {
    scene::Scene s;
    s.point_lights.resize(1);
    s.point_lights[0].near_plane = 0.1f;
    return s;
  }();
  cube::summarize_on_host(flipped);
  Images reference = six_pass;
  cube::summarize_on_host(reference);
  CaseFindings r;
  r.config.layout = Layout::tetrahedral;
  r.config.technique = Technique::geometry_shader;
  check_against_reference(r, flipped, reference, CheckContext{scene, DeviceInfo{}, CheckOptions{}, {}});
  EXPECT_EQ(r.status, Status::failed_check) << r.reason;
}

}  // namespace
}  // namespace omnishadow::bench
