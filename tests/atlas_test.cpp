// Layout atlas's packing (backends/common/atlas.h): every light's block inside the atlas and apart from every
// other, each face's tile inside its block with a border all round, whatever the lights' sizes.

#include "backends/common/atlas.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace omnishadow {
namespace {

struct Rect {
  int x0, y0, x1, y1;  // half-open
  bool overlaps(const Rect& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

Rect block_rect(const atlas::Block& b) {
  return {b.x, b.y, b.x + atlas::block_width(b.face_size), b.y + atlas::block_height(b.face_size)};
}

// Face f's texels with kBorder texels around them.
Rect bordered_tile(const atlas::Block& b, int face) {
  const atlas::Texel o = atlas::face_origin(b, face);
  return {o.x - atlas::kBorder, o.y - atlas::kBorder, o.x + b.face_size + atlas::kBorder,
          o.y + b.face_size + atlas::kBorder};
}

void expect_valid(const atlas::Plan& plan, const std::vector<int>& sizes) {
  ASSERT_EQ(plan.lights.size(), sizes.size());
  std::vector<Rect> tiles;
  for (size_t k = 0; k < sizes.size(); ++k) {
    const atlas::Block& b = plan.lights[k];
    SCOPED_TRACE("light " + std::to_string(k));
    EXPECT_EQ(b.face_size, sizes[k]) << "each light keeps its own face size";
    const Rect r = block_rect(b);
    EXPECT_GE(r.x0, 0);
    EXPECT_GE(r.y0, 0);
    EXPECT_LE(r.x1, plan.width);
    EXPECT_LE(r.y1, plan.height);
    for (int f = 0; f < 6; ++f) {
      const Rect t = bordered_tile(b, f);
      EXPECT_TRUE(t.x0 >= r.x0 && t.y0 >= r.y0 && t.x1 <= r.x1 && t.y1 <= r.y1) << "face " << f;
      tiles.push_back(t);
    }
  }
  // No two faces' bordered tiles share a texel: a lookup clamped to its face's texel centres reads its own
  // tile, and a LINEAR tap at the edge reaches the border, never a neighbour.
  for (size_t i = 0; i < tiles.size(); ++i)
    for (size_t j = i + 1; j < tiles.size(); ++j) EXPECT_FALSE(tiles[i].overlaps(tiles[j])) << i << ", " << j;
}

TEST(Atlas, EqualLightsPackSideBySideWithBorders) {
  const std::vector<int> sizes(4, 32);
  const atlas::Plan plan = atlas::pack(sizes);
  expect_valid(plan, sizes);
  EXPECT_EQ(atlas::block_width(32), 3 * 34);
  EXPECT_EQ(atlas::block_height(32), 2 * 34);
  // Light 0 at the origin, face 0 one border in; face 4 (+Z) in the second row's middle column.
  EXPECT_EQ(plan.lights[0].x, 0);
  EXPECT_EQ(plan.lights[0].y, 0);
  EXPECT_EQ(atlas::face_origin(plan.lights[0], 0).x, 1);
  EXPECT_EQ(atlas::face_origin(plan.lights[0], 0).y, 1);
  EXPECT_EQ(atlas::face_origin(plan.lights[0], 4).x, 34 + 1);
  EXPECT_EQ(atlas::face_origin(plan.lights[0], 4).y, 34 + 1);
  // Four blocks of 102 x 68 in rows no wider than the square root of their area (about 166) plus a block.
  EXPECT_EQ(plan.width, 2 * 102);
  EXPECT_EQ(plan.height, 2 * 68);
}

TEST(Atlas, EachLightItsOwnSizeLargestFirst) {
  const std::vector<int> sizes = {16, 128, 64, 16, 32, 128, 8};
  const atlas::Plan plan = atlas::pack(sizes);
  expect_valid(plan, sizes);
  EXPECT_EQ(plan.lights[1].x, 0) << "the first of the largest leads the first shelf";
  EXPECT_EQ(plan.lights[1].y, 0);
  // Deterministic: the same sizes, the same plan.
  const atlas::Plan again = atlas::pack(sizes);
  for (size_t k = 0; k < sizes.size(); ++k) {
    EXPECT_EQ(again.lights[k].x, plan.lights[k].x);
    EXPECT_EQ(again.lights[k].y, plan.lights[k].y);
  }
  // Not much wasted: the blocks fill at least half of the atlas.
  long long used = 0;
  for (int s : sizes) used += 1LL * atlas::block_width(s) * atlas::block_height(s);
  EXPECT_GE(2 * used, 1LL * plan.width * plan.height);
}

TEST(Atlas, SixtyFourLightsFitTheSmallestDeviceLimitAtCube256) {
  const std::vector<int> sizes(64, 256);
  const atlas::Plan plan = atlas::pack(sizes);
  expect_valid(plan, sizes);
  EXPECT_EQ(atlas::too_large(plan, 8192, "a limit"), "");
  const std::string why =
      atlas::too_large(atlas::pack(std::vector<int>(64, 1024)), 16384, "GL_MAX_TEXTURE_SIZE");
  EXPECT_NE(why.find("64 light(s)"), std::string::npos) << why;
  EXPECT_NE(why.find("GL_MAX_TEXTURE_SIZE"), std::string::npos) << why;
}

TEST(Atlas, UniformTilesGiveEveryLightTheCubeSize) {
  CaseConfig c;
  c.layout = Layout::atlas;
  c.cube_size = 48;
  c.light_count = 5;
  expect_valid(atlas::uniform_plan(c), std::vector<int>(5, 48));
  scene::Scene s;
  s.point_lights.resize(5);  // the lights' places do not matter to uniform tiles
  EXPECT_EQ(atlas::face_sizes(c, s), std::vector<int>(5, 48));
}

// by_distance: --cube halved round(log2(distance / range)) times, at most three, none within range.
TEST(Atlas, TilesByDistanceHalveWithTheLightsShareOfTheView) {
  CaseConfig c;
  c.layout = Layout::atlas;
  c.atlas_tiles = AtlasTiles::by_distance;
  c.cube_size = 256;
  c.light_count = 6;
  scene::Scene s;
  s.point_lights.clear();  // a default scene has a light of its own
  s.camera.position = glm::vec3(0.0f);
  // Ranges 10; distances 5 (inside), 14 (ratio 1.4: round(0.49) = 0), 15 (1.5: 1), 40 (4: 2), 80 (8: 3),
  // 1000.
  for (float d : {5.0f, 14.0f, 15.0f, 40.0f, 80.0f, 1000.0f}) {
    scene::PointLight l;
    l.far_plane = 10.0f;
    l.path.base = glm::vec3(d, 0.0f, 0.0f);
    s.point_lights.push_back(l);
  }
  EXPECT_EQ(atlas::face_sizes(c, s), (std::vector<int>{256, 256, 128, 64, 32, 32}));
  expect_valid(atlas::plan_for(c, s), atlas::face_sizes(c, s));
  const atlas::Plan uniform = atlas::uniform_plan(c);
  const atlas::Plan sized = atlas::plan_for(c, s);
  EXPECT_LT(1LL * sized.width * sized.height, 1LL * uniform.width * uniform.height);
  c.light_count = 7;
  EXPECT_THROW(atlas::face_sizes(c, s), std::logic_error) << "more lights than the scene has";
}

// by_coverage: the camera at the origin looking along +x; lamps of range 2 ahead at growing distances, one
// around the camera, one behind it.
scene::Scene lamps_ahead() {
  scene::Scene s;
  s.point_lights.clear();
  s.camera.position = glm::vec3(0.0f);
  s.camera.target = glm::vec3(1.0f, 0.0f, 0.0f);
  for (glm::vec3 p : {glm::vec3(1.0f, 0, 0), glm::vec3(4.0f, 0, 0), glm::vec3(8.0f, 0, 0),
                      glm::vec3(30.0f, 0, 0), glm::vec3(-10.0f, 0, 0)}) {
    scene::PointLight l;
    l.far_plane = 2.0f;
    l.path.base = p;
    s.point_lights.push_back(l);
  }
  return s;
}

TEST(Atlas, TilesByCoverageFollowTheScreenAreaWithinTheBudget) {
  const scene::Scene s = lamps_ahead();
  EXPECT_EQ(atlas::screen_coverage(s, 0, 400, 300), 1.0) << "the camera inside the range";
  EXPECT_EQ(atlas::screen_coverage(s, 4, 400, 300), 0.0) << "behind the camera";
  EXPECT_GT(atlas::screen_coverage(s, 1, 400, 300), atlas::screen_coverage(s, 2, 400, 300));
  EXPECT_GT(atlas::screen_coverage(s, 2, 400, 300), atlas::screen_coverage(s, 3, 400, 300));
  CaseConfig c;
  c.layout = Layout::atlas;
  c.atlas_tiles = AtlasTiles::by_coverage;
  c.cube_size = 256;
  c.light_count = 5;
  c.width = 400;
  c.height = 300;
  for (uint64_t budget : {uint64_t(0), uint64_t(1) << 20, uint64_t(1) << 18, uint64_t(1) << 16}) {
    c.shadow_budget_texels = budget;
    const std::vector<int> sizes = atlas::face_sizes(c, s);
    const atlas::Plan plan = atlas::plan_for(c, s);
    expect_valid(plan, sizes);
    EXPECT_LE(uint64_t(plan.width) * uint64_t(plan.height), atlas::budget_texels(c)) << budget;
    for (size_t k = 0; k + 2 < sizes.size(); ++k) EXPECT_GE(sizes[k], sizes[k + 1]) << "nearer, larger";
    EXPECT_EQ(sizes[4], atlas::kMinCoverageFace) << "out of view: the smallest";
    EXPECT_EQ(atlas::budget_problem(c), "");
  }
  c.shadow_budget_texels = 0;
  EXPECT_EQ(atlas::face_sizes(c, s)[0], 256) << "the uniform atlas's texels: the nearest keeps --cube";
  c.shadow_budget_texels = 100;
  EXPECT_NE(atlas::budget_problem(c).find("--shadow-budget 100 texels"), std::string::npos);
}

TEST(Atlas, BadSizesAreRefusedByName) {
  EXPECT_THROW(atlas::pack(std::vector<int>{}), std::invalid_argument);
  try {
    atlas::pack(std::vector<int>{16, 0});
    FAIL() << "a face of 0 texels packed";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("got 0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace omnishadow
