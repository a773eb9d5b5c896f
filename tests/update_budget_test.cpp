// The update budget: the planner refreshes the oldest stale faces first within the budget (faces one by one
// where each face is a pass of its own, whole lights otherwise), and the check holds any record of what the
// faces hold to the lights' paths: a face never refreshed, a frame over budget and a face read empty fail.

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "backends/common/case_support.h"
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
  EXPECT_NE(r.reason.find("face -Z has shown its light and casters of frame 0 for 6 frames"),
            std::string::npos)
      << r.reason;
}

TEST(UpdateBudget, CheckFailsAFrameOverBudgetAndAFaceReadEmpty) {
  const bench::CaseFindings over = checked(round_robin(8, [](int t, Frames& held) {
    if (t == 3) held[4] = 3;
  }));
  EXPECT_NE(over.reason.find("frame 3 rendered 2 faces (0 of them first renders of faces that held nothing), "
                             "above the update budget of 1"),
            std::string::npos)
      << over.reason;
  const bench::CaseFindings empty = checked(round_robin(8, [](int t, Frames& held) {
    if (t == 2) held[3] = -1;
  }));
  EXPECT_NE(empty.reason.find("frame 2: light 0 face -Y is read but holds no light's depth"),
            std::string::npos)
      << empty.reason;
}

// A face culled to the view until frame 3 (it holds nothing and is not read at frame 2), then read: its first
// render comes on top of the budget's one face, and the check counts it apart. Two faces rendered where
// neither held nothing still fail.
TEST(UpdateBudget, CheckAllowsAFirstRenderBeyondTheBudgetOnly) {
  const uint8_t all = cube::kAllFaces, but_minus_y = uint8_t(all & ~(1u << 3));
  std::vector<bench::SequenceFrame> frames = {{0, {{0, 0, 0, 0, 0, 0}}, {all}, 0.0, 0},
                                              {1, {{1, 0, 0, -1, 0, 0}}, {but_minus_y}, 0.0, 0},
                                              {2, {{1, 2, 0, -1, 0, 0}}, {but_minus_y}, 0.0, 0},
                                              {3, {{1, 2, 3, 3, 0, 0}}, {all}, 0.0, 0}};
  const bench::CaseFindings first = checked(frames);
  EXPECT_EQ(first.status, bench::Status::ok) << first.reason;
  frames[2].face_frames[0][3] = 0;  // it held frame 0's: rendered again at 3, a refresh like any other
  frames[1].face_frames[0][3] = 0;
  const bench::CaseFindings refresh = checked(frames);
  EXPECT_NE(refresh.reason.find("frame 3 rendered 2 faces (0 of them first renders"), std::string::npos)
      << refresh.reason;
}

// A box of half-size 0.25 at (x, 2, 0), moving `amplitude` either way along z (0.5 rad/s): a caster one
// face of a light at (0, 2, 0) sees.
void add_box(scene::Scene& s, float x, float amplitude) {
  scene::Object o;
  o.first_vertex = uint32_t(s.vertices.size());
  for (float dx : {-0.25f, 0.25f})
    for (float dz : {-0.25f, 0.25f}) s.vertices.push_back({{x + dx, 2.0f, dz}, {0, 1, 0}, {1, 1, 1}});
  s.vertices.resize(s.vertices.size() + 2, s.vertices.back());  // two triangles' worth of vertices
  o.vertex_count = 6;
  o.bounds_min = o.rest_bounds_min = {x - 0.25f, 1.75f, -0.25f};
  o.bounds_max = o.rest_bounds_max = {x + 0.25f, 2.25f, 0.25f};
  o.motion.amplitude = {0.0f, 0.0f, amplitude};
  o.motion.frequency = 0.5f;
  s.objects.push_back(o);
}

// Still lights, one moving box 2 units along -X of light 0 (beyond light 1's range): only light 0's -X face
// goes stale, every frame, and the budget refreshes it; the other faces and light keep their first frame.
TEST(UpdateBudget, AMovingCasterDirtiesTheFacesItReaches) {
  scene::Scene s = lights_scene(2, 0);
  for (scene::PointLight& l : s.point_lights) l.far_plane = 3.0f;
  add_box(s, -2.0f, 0.5f);
  const CaseConfig c = budget_case(Technique::six_pass, 2, 1);
  const auto frames = plan_frames(s, c, 3);
  for (int t = 1; t <= 3; ++t) {
    EXPECT_EQ(frames[size_t(t)][0], (Frames{0, t, 0, 0, 0, 0})) << "frame " << t << ": -X alone, every frame";
    EXPECT_EQ(frames[size_t(t)][1], (Frames{0, 0, 0, 0, 0, 0})) << "the box is beyond light 1's range";
  }
  EXPECT_EQ(cube::moved_caster_faces(s, glm::vec3(0, 2, 0), 0.1f, 3.0f, 0, 0), 0) << "no motion, no face";
}

TEST(UpdateBudget, AStaticCubeIsReusedOnlyWhileNoCasterInRangeMoves) {
  scene::Scene s = lights_scene(1, 0);
  s.point_lights[0].far_plane = 3.0f;
  add_box(s, -2.0f, 0.5f);
  CaseConfig c = budget_case(Technique::six_pass, 1, 0);
  c.layout = Layout::cube;
  c.optimizations.static_cache = true;
  gpu::LightFramePlanner planner;
  planner.reset(1);
  for (int t = 0; t < 3; ++t) {
    const gpu::LightFrames f = planner.prepare(s, t, c, cube::DepthRange::zero_to_one);
    EXPECT_FALSE(f.lights[0].reuse_cube) << "frame " << t << ": the box moved within the light's range";
    planner.rendered(f, c);
  }
  s.objects[0].motion.amplitude = glm::vec3(0.0f);  // standing still: the cube rendered once serves
  EXPECT_TRUE(planner.prepare(s, 3, c, cube::DepthRange::zero_to_one).lights[0].reuse_cube);
}

// The check's own rule: a face a moving caster reaches and that the planner never refreshes fails it.
TEST(UpdateBudget, CheckFailsAFaceAMovingCasterLeftStale) {
  scene::Scene s = lights_scene(1, 0);
  s.point_lights[0].far_plane = 3.0f;
  add_box(s, -2.0f, 0.5f);
  bench::CaseFindings r;
  r.config = budget_case(Technique::six_pass, 1, 1);
  std::vector<bench::SequenceFrame> frames;
  for (int t = 0; t < 6; ++t) frames.push_back({t, {Frames{0, t, 0, 0, 0, 0}}, {cube::kAllFaces}, 0.0, 0});
  check_update_budget(r, s, {0}, frames);
  EXPECT_EQ(r.status, bench::Status::ok) << r.reason;
  ASSERT_TRUE(r.staleness);
  EXPECT_EQ(r.staleness->wait_bound, 0) << "one face can go stale, one refreshed a frame";
  frames.clear();
  for (int t = 0; t < 6; ++t) frames.push_back({t, {Frames{0, 0, 0, 0, 0, 0}}, {cube::kAllFaces}, 0.0, 0});
  bench::CaseFindings never;
  never.config = r.config;
  check_update_budget(never, s, {0}, frames);
  EXPECT_EQ(never.status, bench::Status::failed_check);
  EXPECT_NE(never.reason.find("face -X has shown its light and casters of frame 0 for 1 frames"),
            std::string::npos)
      << never.reason;
}

}  // namespace
}  // namespace omnishadow
