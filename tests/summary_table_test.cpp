// summary.md (bench/report/summary_table.h): an incomplete run says so first, and the accuracy of each filter
// is in it beside what it is held to.
#include "bench/report/summary_table.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace omnishadow::bench {
namespace {

CaseResult with_accuracy(Technique t, Filter f, double misclassified, double mae, double fit_radius) {
  CaseResult r;
  r.config.technique = t;
  r.config.filter = f;
  Accuracy a;
  a.pixels = 1000;
  a.misclassified_percent = misclassified;
  a.mae_point = mae;
  a.fit_radius = fit_radius;
  a.fit_mae_best = fit_radius < 0 ? -1.0 : mae / 2;
  r.accuracy = a;
  return r;
}

TEST(SummaryTable, EachFiltersAccuracyIsBesideWhatItIsHeldTo) {
  const std::vector<CaseResult> results = {
      with_accuracy(Technique::six_pass, Filter::hard, 0.12, 0.0012, 0.0),
      with_accuracy(Technique::geometry_shader, Filter::hard, 9.0, 0.5, 1.6),  // the row's first case speaks
      with_accuracy(Technique::six_pass, Filter::pcf_disk20, 0.226, 0.0048, 0.1),
      with_accuracy(Technique::six_pass, Filter::vsm, 0.45, 0.0058, -1.0)};
  const std::string md = summary_markdown(results);
  const size_t table = md.find("## Accuracy per filter, against exact visibility");
  ASSERT_NE(table, std::string::npos) << md;
  EXPECT_NE(md.find("spherical light whose exact soft shadow the filter matches best", table),
            std::string::npos);
  const size_t row = md.find(
      "| `gl/room/c512/f800x600/linear_depth/d32f` | 0.12% / 0.0012 / r 0 (0.0006) | - | "
      "0.226% / 0.0048 / r 0.1 (0.0024) |",
      table);
  EXPECT_NE(row, std::string::npos) << md;
  EXPECT_NE(md.find("| 0.45% / 0.0058 |", table), std::string::npos) << "no fit: two figures\n" << md;
  EXPECT_EQ(md.find("9%"), std::string::npos) << "a later technique's figures do not replace six_pass's";
  EXPECT_EQ(md.find("Incomplete"), std::string::npos) << "a whole run has no banner";
}

// Hard filters' false and missed shadows, where many, are named with what mends them; soft filters' are by
// design and are not.
TEST(SummaryTable, AcneAndLeaksOfHardFiltersAreNamed) {
  std::vector<CaseResult> results = {with_accuracy(Technique::six_pass, Filter::hard, 2.4, 0.02, -1.0),
                                     with_accuracy(Technique::six_pass, Filter::pcf_disk20, 3.0, 0.03, 0.1)};
  results[0].config.cube_size = 256;
  results[0].accuracy->false_shadow_percent = 1.95;
  results[0].accuracy->missed_shadow_percent = 0.43;
  results[1].accuracy->false_shadow_percent = 2.0;
  results[1].accuracy->missed_shadow_percent = 1.5;
  const std::string md = summary_markdown(results);
  EXPECT_NE(
      md.find("## What the errors are\n\n- `gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f`: "
              "1.95% of pixels shadowed where the light is visible (acne): the lookup's bias is short of "
              "the depth a texel spans on grazing receivers at cube 256"),
      std::string::npos)
      << md;
  EXPECT_EQ(md.find("hidden (leaks)"), std::string::npos) << "0.43% missed is below the note's 1%";
  EXPECT_EQ(md.find("pcf_disk20/linear_depth/d32f`:"), std::string::npos) << "a soft filter blurs by design";
  results[0].accuracy->false_shadow_percent = 0.2;
  EXPECT_EQ(summary_markdown(results).find("## What the errors are"), std::string::npos);
}

TEST(SummaryTable, AnIncompleteRunSaysSoFirst) {
  const std::string md =
      summary_markdown({}, {}, {}, "stopped by SIGINT during the untimed checks, after 3 of 9 cases");
  EXPECT_EQ(
      md.rfind("**Incomplete run: stopped by SIGINT during the untimed checks, after 3 of 9 cases.**", 0), 0u)
      << md;
}

// A run that timed nothing (every case unsupported) shows no empty timing tables and no ratio of two
// near-zero parts; a run that timed cases shows both.
TEST(SummaryTable, ARunThatTimedNothingHasNoTimingTablesOrPhaseRatio) {
  CaseResult unsupported;
  unsupported.status = Status::unsupported;
  RunPhases tiny;
  tiny.untimed_seconds = 0.0007;
  tiny.timed_seconds = 0.00001;
  const std::string md = summary_markdown({unsupported}, tiny);
  EXPECT_NE(md.find("Run: 0.0 s untimed (checks, read-backs, reference, images) + 0.0 s timed\n"),
            std::string::npos)
      << md;
  EXPECT_EQ(md.find("the timed part)"), std::string::npos) << md;
  EXPECT_EQ(md.find("median wall time"), std::string::npos) << md;

  CaseResult timed = with_accuracy(Technique::six_pass, Filter::hard, 0.1, 0.001, -1.0);
  timed.frames = {FrameTiming{}};
  RunPhases measured;
  measured.untimed_seconds = 3.0;
  measured.timed_seconds = 2.0;
  const std::string both = summary_markdown({unsupported, timed}, measured);
  EXPECT_NE(both.find("+ 2.0 s timed (1.50x the timed part)"), std::string::npos) << both;
  EXPECT_NE(both.find("## Shadow pass: median wall time per technique"), std::string::npos) << both;
  EXPECT_NE(both.find("## Lighting pass: median wall time per filter"), std::string::npos) << both;
}

// A run over several light counts gets a row per case whose cells are the cost per light and the pooled error
// at each count; a run with one count has no such table.
TEST(SummaryTable, ManyLightsRowsGiveTheCostPerLightAtEachCount) {
  auto timed = [](int lights, double frame_ms, double misclassified) {
    CaseResult r = with_accuracy(Technique::six_pass, Filter::hard, misclassified, 0.01, -1.0);
    r.config.scene = "hall";
    r.config.layout = Layout::cube_array;
    r.config.light_count = lights;
    FrameTiming f;
    f.shadow.cpu_wall_ms = frame_ms / 2;
    f.frame_wall_ms = frame_ms;
    r.frames = {f, f, f};
    return r;
  };
  const std::vector<CaseResult> one = {timed(1, 4.0, 2.0)};
  EXPECT_EQ(summary_markdown(one).find("## Many lights"), std::string::npos);
  const std::string md = summary_markdown({timed(1, 4.0, 2.0), timed(4, 12.0, 1.5)});
  const size_t table = md.find("## Many lights: cost per light and error against the number of lights");
  ASSERT_NE(table, std::string::npos) << md;
  EXPECT_NE(md.find("| case (K = 1 id) | 1 light | 4 lights |", table), std::string::npos) << md;
  EXPECT_NE(
      md.find("| `gl/hall/c512/f800x600/six_pass/hard/linear_depth/d32f/cube_array` | 2.00 / 4.00 ms, 2.0% | "
              "1.50 / 3.00 ms, 1.5% |",
              table),
      std::string::npos)
      << md;
}

// The staleness table: a sequence without error measured (--no-accuracy) reads like one with it, and where a
// case re-plans its atlas, every row says how many lights the re-plans moved (and in how many frames).
TEST(SummaryTable, StalenessRowsCountTheLightsReplansMoved) {
  auto sequence = [](int replan, std::vector<int> relocated, bool measured) {
    CaseResult r;
    r.config.layout = Layout::atlas;
    r.config.atlas_tiles = AtlasTiles::by_distance;
    r.config.atlas_replan_frames = replan;
    StalenessReport s;
    for (size_t t = 0; t < relocated.size(); ++t)
      s.frames.push_back({int(t), 6, 0, 0, 0.5, 100, relocated[t]});
    s.mean_faces_rendered = 6.25;
    if (measured) {
      s.lights = {0};
      s.mean_misclassified_percent = 0.5;
      s.worst_misclassified_percent = 0.5;
    }
    r.staleness = s;
    return r;
  };
  const std::string once = summary_markdown({sequence(0, {0, 0, 0}, true)});
  EXPECT_EQ(once.find("moved by re-plans"), std::string::npos) << "no re-plans, no column\n" << once;
  const std::string md = summary_markdown({sequence(0, {0, 0, 0}, true), sequence(1, {0, 2, 0, 1}, false)});
  const size_t table = md.find("## Staleness over a sequence of frames");
  ASSERT_NE(table, std::string::npos) << md;
  EXPECT_NE(md.find("| longest wait, frames | misclassified, mean | worst | moved by re-plans |", table),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("/tiles_by_distance` | 3 | 6.2 | 0 (bound 0) | 0.5% | 0.5% (frame 0) | - |", table),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("/tiles_by_distance/replan1` | 4 | 6.2 | 0 (bound 0) | - | - | 3 (2) |", table),
            std::string::npos)
      << md;
}

}  // namespace
}  // namespace omnishadow::bench
