// Atlas re-plans (CaseConfig::atlas_replan_frames): as the camera walks past still lamps, each re-plan sizes
// the tiles from that frame's view and packs them into the atlas as allocated; the planner renders again
// exactly the lights whose blocks moved, and the update budget's check counts those renders apart.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "backends/common/atlas.h"
#include "backends/common/layouts.h"
#include "backends/common/shadow_frame.h"
#include "bench/truth/case_checks.h"
#include "scenes/scene.h"

namespace omnishadow {
namespace {

// Eight still lamps of range 4 along +x, 6 units apart; the camera looks down +x from x = -10 and walks
// 40 units along it (0.5 rad/s sway, frame 188 near its far end), so that lamps pass from far to near.
scene::Scene lamps_along_a_walk() {
  scene::Scene s;
  s.point_lights.clear();
  for (int k = 0; k < 8; ++k) {
    scene::PointLight l;
    l.far_plane = 4.0f;
    l.path.base = glm::vec3(float(6 * k), 0.0f, 1.0f);
    s.point_lights.push_back(l);
  }
  s.camera.position = glm::vec3(-10.0f, 0.0f, 0.0f);
  s.camera.target = glm::vec3(0.0f, 0.0f, 0.0f);
  s.camera.path.amplitude = glm::vec3(40.0f, 0.0f, 0.0f);
  s.camera.path.frequency = 0.5f;
  return s;
}

CaseConfig replan_case(AtlasTiles tiles, int every) {
  CaseConfig c;
  c.layout = Layout::atlas;
  c.atlas_tiles = tiles;
  c.atlas_replan_frames = every;
  c.cube_size = 64;
  c.light_count = 8;
  c.width = 320;
  c.height = 240;
  if (tiles == AtlasTiles::by_coverage) c.shadow_budget_texels = 96 * 1024;
  return c;
}

bool same_block(const atlas::Block& a, const atlas::Block& b) {
  return std::tie(a.x, a.y, a.face_size) == std::tie(b.x, b.y, b.face_size);
}

std::vector<int> sizes_of(const atlas::Plan& p) {
  std::vector<int> sizes;
  for (const atlas::Block& b : p.lights) sizes.push_back(b.face_size);
  return sizes;
}

// Every block inside the allocated atlas and apart from every other (atlas_test.cpp holds the tiles within
// a block).
void expect_blocks_fit(const atlas::Plan& p, int width, int height) {
  EXPECT_EQ(p.width, width);
  EXPECT_EQ(p.height, height);
  for (size_t i = 0; i < p.lights.size(); ++i) {
    const atlas::Block& a = p.lights[i];
    EXPECT_TRUE(a.x >= 0 && a.y >= 0 && a.x + atlas::block_width(a.face_size) <= width &&
                a.y + atlas::block_height(a.face_size) <= height)
        << "light " << i;
    for (size_t j = i + 1; j < p.lights.size(); ++j) {
      const atlas::Block& b = p.lights[j];
      const bool apart =
          a.x + atlas::block_width(a.face_size) <= b.x || b.x + atlas::block_width(b.face_size) <= a.x ||
          a.y + atlas::block_height(a.face_size) <= b.y || b.y + atlas::block_height(b.face_size) <= a.y;
      EXPECT_TRUE(apart) << "lights " << i << " and " << j;
    }
  }
}

TEST(AtlasReplan, EveryReplanFitsTheAtlasAsAllocated) {
  const scene::Scene s = lamps_along_a_walk();
  for (AtlasTiles tiles : {AtlasTiles::by_distance, AtlasTiles::by_coverage}) {
    SCOPED_TRACE(std::string(to_string(tiles)));
    const CaseConfig c = replan_case(tiles, 8);
    const atlas::Plan allocated = atlas::plan_for(c, s);
    if (tiles == AtlasTiles::by_distance) {
      const atlas::Plan uniform = atlas::uniform_plan(c);
      EXPECT_EQ(std::tie(allocated.width, allocated.height), std::tie(uniform.width, uniform.height))
          << "by_distance keeps the uniform atlas: no tile is larger than --cube";
    } else {
      EXPECT_LE(uint64_t(allocated.width) * uint64_t(allocated.height), atlas::budget_texels(c));
    }
    int changes = 0;
    std::vector<int> before = sizes_of(allocated);
    for (int t = 0; t <= 200; ++t) {
      SCOPED_TRACE("frame " + std::to_string(t));
      const atlas::Plan p = atlas::plan_at(c, s, t);
      expect_blocks_fit(p, allocated.width, allocated.height);
      const int planned = atlas::planned_frame(c, t);
      EXPECT_EQ(planned, t - t % 8);
      if (tiles == AtlasTiles::by_distance) {
        EXPECT_EQ(sizes_of(p), atlas::face_sizes(c, s, planned));
      }
      const atlas::Plan at_plan = atlas::plan_at(c, s, planned);
      for (size_t k = 0; k < p.lights.size(); ++k) EXPECT_TRUE(same_block(p.lights[k], at_plan.lights[k]));
      changes += sizes_of(p) != before;
      before = sizes_of(p);
    }
    EXPECT_GT(changes, 1) << "the walk re-sizes the tiles more than once";
    CaseConfig once = c;
    once.atlas_replan_frames = 0;
    EXPECT_EQ(atlas::planned_frame(once, 188), 0);
    EXPECT_EQ(sizes_of(atlas::plan_at(once, s, 188)), sizes_of(atlas::plan_for(once, s)))
        << "without re-plans every frame keeps frame 0's tiles";
  }
}

TEST(AtlasReplan, PackIntoKeepsTheAtlasSizeOrSaysItCannot) {
  const std::vector<int> sizes = {32, 16, 16, 8};
  const std::optional<atlas::Plan> p = atlas::pack_into(sizes, 300, 200);
  ASSERT_TRUE(p.has_value());
  expect_blocks_fit(*p, 300, 200);
  EXPECT_EQ(sizes_of(*p), sizes);
  EXPECT_FALSE(atlas::pack_into(sizes, atlas::block_width(32) - 1, 1000).has_value()) << "too narrow";
  EXPECT_FALSE(atlas::pack_into(sizes, 1000, atlas::block_height(32) - 1).has_value()) << "too low";
}

// A re-plan keeps every block whose size held: four blocks, one grown, the other three where they were and
// the grown one in the space left; one grown beyond any space left gets no placement (replan packs afresh).
TEST(AtlasReplan, PlacingKeepsTheBlocksWhoseSizeHeld) {
  const atlas::Plan before = *atlas::pack_into(std::vector<int>{16, 16, 16, 16}, 400, 200);
  const std::vector<int> grown = {16, 32, 16, 16};
  const std::optional<atlas::Plan> p = atlas::place_keeping(before, grown);
  ASSERT_TRUE(p.has_value());
  expect_blocks_fit(*p, 400, 200);
  EXPECT_EQ(sizes_of(*p), grown);
  for (size_t k : {0u, 2u, 3u}) EXPECT_TRUE(same_block(p->lights[k], before.lights[k])) << "light " << k;
  EXPECT_FALSE(atlas::place_keeping(before, std::vector<int>{16, 100, 16, 16}).has_value()) << "no room";
}

// Along the walk, each re-plan moves exactly the lights whose size changed (no fresh packing was needed).
TEST(AtlasReplan, AlongTheWalkOnlyTheResizedLightsMove) {
  const scene::Scene s = lamps_along_a_walk();
  for (AtlasTiles tiles : {AtlasTiles::by_distance, AtlasTiles::by_coverage}) {
    SCOPED_TRACE(std::string(to_string(tiles)));
    const CaseConfig c = replan_case(tiles, 1);
    atlas::Plan was = atlas::plan_for(c, s);
    int resized = 0;
    for (int t = 1; t <= 200; ++t) {
      const atlas::Plan now = atlas::replan(c, s, t, was);
      for (size_t k = 0; k < now.lights.size(); ++k) {
        const bool same_size = now.lights[k].face_size == was.lights[k].face_size;
        resized += !same_size;
        EXPECT_EQ(same_block(now.lights[k], was.lights[k]), same_size) << "frame " << t << " light " << k;
      }
      was = now;
    }
    EXPECT_GT(resized, 1);
    EXPECT_TRUE(std::equal(was.lights.begin(), was.lights.end(), atlas::plan_at(c, s, 200).lights.begin(),
                           same_block))
        << "the chain plan_at walks";
  }
}

// Still lamps and static caching: at a re-plan the lights whose blocks moved render whole (their texels are
// elsewhere now), the others keep their maps, and every record carries the new tiles.
TEST(AtlasReplan, APlannerRendersAgainTheLightsAReplanMoves) {
  scene::Scene s = lamps_along_a_walk();
  CaseConfig c = replan_case(AtlasTiles::by_distance, 1);
  c.optimizations.static_cache = true;
  gpu::LightFramePlanner planner;
  planner.reset(c.light_count, atlas::plan_for(c, s));
  gpu::LightFrames f = planner.prepare(s, 0, c, cube::DepthRange::zero_to_one);
  planner.rendered(f, c);
  int moved_total = 0, kept_total = 0;
  atlas::Plan was = atlas::plan_for(c, s);
  for (int t = 1; t <= 188; t += 11) {
    SCOPED_TRACE("frame " + std::to_string(t));
    f = planner.prepare(s, t, c, cube::DepthRange::zero_to_one);
    const atlas::Plan now = atlas::plan_at(c, s, t);
    int moved = 0;
    for (size_t k = 0; k < now.lights.size(); ++k) {
      const bool relocated = !same_block(was.lights[k], now.lights[k]);
      moved += relocated;
      EXPECT_EQ(f.lights[k].reuse_cube, !relocated) << "light " << k;
      const atlas::Block& b = now.lights[k];
      EXPECT_EQ(f.records[k].atlas_tile, glm::vec4(float(b.x), float(b.y), float(b.face_size), 1.0f));
      EXPECT_EQ(f.lights[k].uniforms.raster_knobs.x, float(c.cube_size) / float(b.face_size))
          << "--raster-perturb's step scaled to the light's tile";
    }
    EXPECT_EQ(f.atlas_relocated, moved);
    EXPECT_EQ(f.atlas_replanned, moved > 0);
    ASSERT_TRUE(planner.atlas().has_value());
    EXPECT_EQ(sizes_of(*planner.atlas()), sizes_of(now));
    moved_total += moved;
    kept_total += int(now.lights.size()) - moved;
    planner.rendered(f, c);
    was = now;
  }
  EXPECT_GT(moved_total, 0) << "the walk moves blocks";
  EXPECT_GT(kept_total, 0) << "and keeps some";
}

// --raster-perturb's step is the pass target's own: the uniforms scale it by --cube / the target's edge, the
// light's tile in an atlas (above), a paraboloid's or tetrahedron's layer (larger than --cube) elsewhere.
TEST(AtlasReplan, EveryLayoutsPerturbationStepIsItsTargets) {
  scene::Scene s = lamps_along_a_walk();
  for (Layout layout : {Layout::cube, Layout::cube_array, Layout::dual_paraboloid, Layout::tetrahedral}) {
    CaseConfig c = replan_case(AtlasTiles::uniform, 0);
    c.layout = layout;
    gpu::LightFramePlanner planner;
    planner.reset(c.light_count);
    const gpu::LightFrames f = planner.prepare(s, 0, c, cube::DepthRange::zero_to_one);
    const float want = float(c.cube_size) / float(layer_size(layout, c.cube_size));
    for (const gpu::ShadowFrame& light : f.lights)
      EXPECT_EQ(light.uniforms.raster_knobs.x, want) << to_string(layout);
  }
}

// Hysteresis: one lamp of range 1 whose distance from a swaying camera crosses by_distance's edge between
// --cube and --cube / 2 (ratio sqrt 2) every half sway. Re-planned by that frame alone it resizes, and
// renders whole, at each crossing; with a quarter octave of hysteresis its need never leaves 2^(1/4) of the
// edge, so it keeps frame 0's size.
TEST(AtlasReplan, HysteresisKeepsALampSwayingAcrossASizesEdge) {
  scene::Scene s;
  s.point_lights.assign(1, scene::PointLight{});
  s.point_lights[0].far_plane = 1.0f;
  s.camera.position = glm::vec3(-1.45f, 0.0f, 0.0f);  // ratio 1.45 +- 0.12: log2 0.41 to 0.65
  s.camera.target = glm::vec3(0.0f);
  s.camera.path.amplitude = glm::vec3(0.12f, 0.0f, 0.0f);
  s.camera.path.frequency = 30.0f;  // a sway every 12.6 frames
  for (float octaves : {0.0f, 0.25f}) {
    SCOPED_TRACE("hysteresis " + std::to_string(octaves));
    CaseConfig c = replan_case(AtlasTiles::by_distance, 1);
    c.light_count = 1;
    c.atlas_hysteresis_octaves = octaves;
    atlas::Plan was = atlas::plan_for(c, s);
    EXPECT_EQ(was.lights[0].face_size, 32) << "frame 0: ratio 1.45, past the edge";
    int resized = 0;
    for (int t = 1; t <= 100; ++t) {
      const atlas::Plan now = atlas::replan(c, s, t, was);
      resized += now.lights[0].face_size != was.lights[0].face_size;
      was = now;
    }
    if (octaves == 0.0f) {
      EXPECT_GE(resized, 10) << "two crossings a sway, about 8 sways";
    } else {
      EXPECT_EQ(resized, 0);
    }
  }
}

// The rule by_distance's sizes follow (atlas.h face_sizes), for a need scaled by `f`: the test's own.
int distance_rule(const CaseConfig& c, double ratio, double f) {
  const double r = ratio / f;
  return r <= 1.0 ? c.cube_size
                  : std::max(1, c.cube_size >> std::clamp(int(std::lround(std::log2(r))), 0, 3));
}

// Along the walk with hysteresis, each lamp at each re-plan has either its size from before (by distance
// while the rule gives it for a need within 2^H of its own) or the frame's own size; the plans fit the
// atlas, move only the resized lamps, and resize fewer than without (by coverage too, where a step of the
// scale resized many lamps at once, and where holding sizes must still fit the budget).
TEST(AtlasReplan, HysteresisHoldsASizeOnlyWhileTheNeedIsWithinItsOctaves) {
  const scene::Scene s = lamps_along_a_walk();
  for (AtlasTiles tiles : {AtlasTiles::by_distance, AtlasTiles::by_coverage}) {
    SCOPED_TRACE(std::string(to_string(tiles)));
    std::vector<int> resized;
    for (float octaves : {0.0f, 0.5f}) {
      CaseConfig c = replan_case(tiles, 1);
      c.atlas_hysteresis_octaves = octaves;
      const double by = std::exp2(double(octaves));
      atlas::Plan was = atlas::plan_for(c, s);
      int count = 0, held_apart = 0;
      for (int t = 1; t <= 200; ++t) {
        SCOPED_TRACE("frame " + std::to_string(t));
        const atlas::Plan now = atlas::replan(c, s, t, was);
        expect_blocks_fit(now, was.width, was.height);
        const std::vector<int> fresh = atlas::face_sizes_within(c, s, t, was.width, was.height);
        for (size_t k = 0; k < now.lights.size(); ++k) {
          const int before = was.lights[k].face_size, size = now.lights[k].face_size;
          count += size != before;
          EXPECT_EQ(same_block(now.lights[k], was.lights[k]), size == before) << "light " << k;
          EXPECT_TRUE(size == before || size == fresh[k]) << "light " << k << ": held, or the frame's own";
          if (tiles != AtlasTiles::by_distance) continue;
          const double ratio = atlas::distance_over_range(s, int(k), t);
          const bool within =
              distance_rule(c, ratio, 1.0 / by) <= before && before <= distance_rule(c, ratio, by);
          EXPECT_EQ(size, within ? before : distance_rule(c, ratio, 1.0)) << "light " << k;
          held_apart += size != distance_rule(c, ratio, 1.0);
        }
        was = now;
      }
      if (tiles == AtlasTiles::by_distance && octaves > 0.0f) {
        EXPECT_GT(held_apart, 0) << "some size held";
      }
      resized.push_back(count);
    }
    if (tiles == AtlasTiles::by_distance) {
      EXPECT_LT(resized[1], resized[0]) << "hysteresis resizes fewer lamps";
    } else {  // the fill already keeps a step of the scale from resizing a share of the lamps at once
      EXPECT_LE(resized[1], resized[0]) << "hysteresis resizes no more lamps";
    }
  }
}

// The hall's walk (docs/many-lights.md, "Tiles that follow the walk"): 24 lamps by coverage within 128K
// texels.
scene::Scene walked_hall() {
  scene::LoadOptions load;
  load.camera = scene::CameraPlacement{glm::dvec3(0, 3, 0), glm::dvec3(20, 2, 0), glm::vec3(-16, 0, 0)};
  return scene::load_scene_file(std::string(OMNISHADOW_TEST_SCENES_DIR) + "/hall.json", load);
}

CaseConfig walked_hall_case(float octaves) {
  CaseConfig c = replan_case(AtlasTiles::by_coverage, 1);
  c.light_count = 24;
  c.width = 200;
  c.height = 150;
  c.shadow_budget_texels = 128 * 1024;
  c.atlas_hysteresis_octaves = octaves;
  return c;
}

// Each re-plan by coverage fills the atlas it keeps: no lamp in view below --cube could double and still fit
// (the quarter step of the scale that fits left 40512 of 115872 texels to blocks at frame 188).
TEST(AtlasReplan, AReplanByCoverageFillsTheAtlasItKeeps) {
  const scene::Scene s = walked_hall();
  const CaseConfig c = walked_hall_case(0.0f);
  const atlas::Plan allocated = atlas::plan_for(c, s);
  for (int t = 0; t <= 188; t += 4) {
    SCOPED_TRACE("frame " + std::to_string(t));
    const std::vector<int> sizes = sizes_of(atlas::plan_at(c, s, t));
    EXPECT_EQ(sizes, atlas::face_sizes_within(c, s, t, allocated.width, allocated.height));
    for (size_t k = 0; k < sizes.size(); ++k) {
      if (sizes[k] >= c.cube_size || atlas::screen_coverage(s, int(k), c.width, c.height, t) <= 0.0) continue;
      std::vector<int> doubled = sizes;
      doubled[k] *= 2;
      EXPECT_FALSE(atlas::pack_into(doubled, allocated.width, allocated.height).has_value())
          << "light " << k << " at " << sizes[k] << " could double";
    }
  }
}

// Held sizes overflow the atlas at frame 17 (the view takes in more lamps and the scale drops): the lamps
// held furthest above their frame's size give it up until the plan fits, and the walk still resizes fewer
// lamps than without hysteresis.
TEST(AtlasReplan, HeldCoverageSizesGiveWayToFitTheBudget) {
  const scene::Scene s = walked_hall();
  std::vector<int> moved;
  for (float octaves : {0.0f, 0.5f}) {
    const CaseConfig c = walked_hall_case(octaves);
    atlas::Plan was = atlas::plan_for(c, s);
    int count = 0;
    for (int t = 1; t <= 188; ++t) {
      const atlas::Plan now = atlas::replan(c, s, t, was);
      expect_blocks_fit(now, was.width, was.height);
      for (uint8_t m : atlas::moved_blocks(was, now)) count += m;
      was = now;
    }
    moved.push_back(count);
  }
  EXPECT_LT(moved[1], moved[0]);
}

// A light a re-plan moved renders its six faces at once, outside the update budget of one light (6 faces):
// frame 2 renders light 1 (stale) and light 0 (moved), 12 faces, and passes; unmarked, it fails.
TEST(AtlasReplan, TheBudgetCheckCountsAMovedLightApart) {
  const uint8_t all = cube::kAllFaces;
  CaseConfig c;
  c.layout = Layout::atlas;
  c.technique = Technique::six_pass;
  c.light_count = 2;
  c.update_budget_faces = 6;
  using F = std::array<int, 6>;
  std::vector<bench::SequenceFrame> frames = {
      {0, {F{0, 0, 0, 0, 0, 0}, F{0, 0, 0, 0, 0, 0}}, {all, all}, 0.0, 0, {}},
      {1, {F{0, 0, 0, 0, 0, 0}, F{0, 0, 0, 0, 0, 0}}, {all, all}, 0.0, 0, {0, 0}},
      {2, {F{2, 2, 2, 2, 2, 2}, F{2, 2, 2, 2, 2, 2}}, {all, all}, 0.0, 0, {1, 0}}};
  scene::Scene s;
  s.point_lights.assign(2, scene::PointLight{});
  bench::CaseFindings moved;
  moved.config = c;
  bench::check_update_budget(moved, s, {}, frames);
  EXPECT_EQ(moved.status, bench::Status::ok) << moved.reason;
  frames[2].relocated = {0, 0};
  bench::CaseFindings unmarked;
  unmarked.config = c;
  bench::check_update_budget(unmarked, s, {}, frames);
  EXPECT_NE(unmarked.reason.find("frame 2 rendered 12 faces (0 of them first renders"), std::string::npos)
      << unmarked.reason;
}

// A light a re-plan moved that keeps a face from before (the planner forgot to render it again) fails, named.
TEST(AtlasReplan, TheCheckFailsAMovedLightThatKeptAFace) {
  const uint8_t all = cube::kAllFaces, but_minus_y = uint8_t(all & ~(1u << 3));
  CaseConfig c;
  c.layout = Layout::atlas;
  c.technique = Technique::six_pass;
  c.light_count = 1;
  using F = std::array<int, 6>;
  std::vector<bench::SequenceFrame> frames = {{0, {F{0, 0, 0, 0, 0, 0}}, {all}, 0.0, 0, {}},
                                              {1, {F{1, 1, 1, -1, 1, 1}}, {but_minus_y}, 0.0, 0, {1}}};
  scene::Scene s;
  s.point_lights.assign(1, scene::PointLight{});
  bench::CaseFindings whole;
  whole.config = c;
  bench::check_update_budget(whole, s, {}, frames);
  EXPECT_EQ(whole.status, bench::Status::ok) << whole.reason << " (a face culled to the view holds nothing)";
  frames[1].face_frames[0][4] = 0;
  bench::CaseFindings kept;
  kept.config = c;
  bench::check_update_budget(kept, s, {}, frames);
  EXPECT_NE(
      kept.reason.find("frame 1: an atlas re-plan moved light 0's block, but its face +Z holds frame 0's"),
      std::string::npos)
      << kept.reason;
}

}  // namespace
}  // namespace omnishadow
