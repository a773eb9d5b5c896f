// The update budget: the planner refreshes the oldest stale faces first within the budget (faces one by one
// where each face is a pass of its own, whole lights otherwise), and the check holds any record of what the
// faces hold to the lights' paths: a face never refreshed, a frame over budget and a face read empty fail.

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "backends/common/shadow_frame.h"
#include "bench/truth/case_checks.h"

namespace omnishadow {
namespace {

using Frames = std::array<int, 6>;

// Lights along x, `moving` of them first swaying (every frame moves them), the rest standing still.
scene::Scene lights_scene(int lights, int moving) {
  scene::Scene s;
  s.point_lights.clear();
  for (int k = 0; k < lights; ++k) {
    scene::PointLight l;
    l.path.base = glm::vec3(float(4 * k), 2.0f, 0.0f);
    if (k < moving) l.path.amplitude = glm::vec3(1.0f, 0.0f, 0.0f), l.path.frequency = 0.5f;
    s.point_lights.push_back(l);
  }
  return s;
}

CaseConfig budget_case(Technique technique, int lights, int budget) {
  CaseConfig c;
  c.technique = technique;
  c.layout = Layout::face_array;
  c.light_count = lights;
  c.update_budget_faces = budget;
  return c;
}

// Renders frames 0..last through the planner as a backend does (prepare, then rendered), returning what
// each light's faces hold after every frame.
std::vector<std::vector<Frames>> plan_frames(scene::Scene& s, const CaseConfig& c, int last) {
  gpu::LightFramePlanner planner;
  planner.reset(c.light_count);
  std::vector<std::vector<Frames>> out;
  for (int t = 0; t <= last; ++t) {
    const gpu::LightFrames f = planner.prepare(s, t, c, cube::DepthRange::zero_to_one);
    planner.rendered(f, c);
    out.push_back(planner.face_frames());
  }
  return out;
}

TEST(UpdateBudget, SingleFacesOldestFirstWithinTheBudget) {
  scene::Scene s = lights_scene(2, 1);
  const CaseConfig c = budget_case(Technique::six_pass, 2, 4);
  ASSERT_TRUE(refreshes_single_faces(c));
  const auto frames = plan_frames(s, c, 3);
  EXPECT_EQ(frames[0][0], (Frames{0, 0, 0, 0, 0, 0})) << "the first frame renders every light whole";
  EXPECT_EQ(frames[0][1], (Frames{0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(frames[1][0], (Frames{1, 1, 1, 1, 0, 0})) << "four of the six stale faces, in face order";
  EXPECT_EQ(frames[2][0], (Frames{2, 2, 1, 1, 2, 2})) << "the two left waiting go first";
  EXPECT_EQ(frames[3][0], (Frames{3, 3, 3, 3, 2, 2}));
  for (const auto& frame : frames) EXPECT_EQ(frame[1], (Frames{0, 0, 0, 0, 0, 0})) << "a still light is kept";
}

TEST(UpdateBudget, WholeLightsWhereOnePassRendersEveryFace) {
  scene::Scene s = lights_scene(2, 2);
  const CaseConfig c = budget_case(Technique::geometry_shader, 2, 6);
  ASSERT_FALSE(refreshes_single_faces(c));
  const auto frames = plan_frames(s, c, 2);
  EXPECT_EQ(frames[1][0], (Frames{1, 1, 1, 1, 1, 1}));
  EXPECT_EQ(frames[1][1], (Frames{0, 0, 0, 0, 0, 0})) << "the budget holds one light's faces";
  EXPECT_EQ(frames[2][1], (Frames{2, 2, 2, 2, 2, 2})) << "the light stale since frame 1 goes first";
  EXPECT_EQ(frames[2][0], (Frames{1, 1, 1, 1, 1, 1}));
}

TEST(UpdateBudget, AtLeastOneLightsFacesWhereLightsRefreshWhole) {
  EXPECT_FALSE(common_support(budget_case(Technique::geometry_shader, 2, 5)).ok);
  EXPECT_TRUE(common_support(budget_case(Technique::six_pass, 2, 1)).ok);
  CaseConfig cached = budget_case(Technique::six_pass, 2, 4);
  cached.optimizations.static_cache = true;
  EXPECT_FALSE(common_support(cached).ok);
}

// One light swaying every frame, every face read: a sequence as a budget of one face a frame renders it
// (round robin from frame 1), with `edit` applied to what the faces hold.
std::vector<bench::SequenceFrame> round_robin(int frames, void (*edit)(int t, Frames& held) = nullptr) {
  std::vector<bench::SequenceFrame> out;
  Frames held{0, 0, 0, 0, 0, 0};
  for (int t = 0; t < frames; ++t) {
    if (t > 0) held[size_t((t - 1) % 6)] = t;
    Frames shown = held;
    if (edit) edit(t, shown);
    out.push_back({t, {shown}, {cube::kAllFaces}, 0.0, 0});
  }
  return out;
}

bench::CaseFindings checked(const std::vector<bench::SequenceFrame>& frames) {
  bench::CaseFindings r;
  r.config = budget_case(Technique::six_pass, 1, 1);
  check_update_budget(r, lights_scene(1, 1), {0}, frames);
  return r;
}

TEST(UpdateBudget, CheckPassesARoundRobinWithinItsBound) {
  const bench::CaseFindings r = checked(round_robin(20));
  EXPECT_EQ(r.status, bench::Status::ok) << r.reason;
  ASSERT_TRUE(r.staleness);
  EXPECT_EQ(r.staleness->wait_bound, 5) << "six faces, one a frame";
  EXPECT_EQ(r.staleness->max_wait, 5);
  EXPECT_EQ(r.staleness->frames[7].faces_rendered, 1);
  EXPECT_EQ(r.staleness->frames[7].faces_stale, 5);
}

TEST(UpdateBudget, CheckFailsAFaceNeverRefreshed) {
  const bench::CaseFindings r = checked(round_robin(20, [](int, Frames& held) { held[5] = 0; }));
  EXPECT_EQ(r.status, bench::Status::failed_check);
  EXPECT_NE(r.reason.find("face -Z has shown its light's position of frame 0 for 6 frames"),
            std::string::npos)
      << r.reason;
}

TEST(UpdateBudget, CheckFailsAFrameOverBudgetAndAFaceReadEmpty) {
  const bench::CaseFindings over = checked(round_robin(8, [](int t, Frames& held) {
    if (t == 3) held[4] = 3;
  }));
  EXPECT_NE(over.reason.find("frame 3 rendered 2 faces, above the update budget of 1"), std::string::npos)
      << over.reason;
  const bench::CaseFindings empty = checked(round_robin(8, [](int t, Frames& held) {
    if (t == 2) held[3] = -1;
  }));
  EXPECT_NE(empty.reason.find("frame 2: light 0 face -Y is read but holds no light's depth"),
            std::string::npos)
      << empty.reason;
}

}  // namespace
}  // namespace omnishadow
