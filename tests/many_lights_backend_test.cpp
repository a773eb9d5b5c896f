// Many point lights on every backend: each light's layers of the shared texture hold exactly what that light
// renders alone, its shadow factor is the one-light case's, the single-pass techniques reproduce six_pass
// light by light, and a read-back of another light is refused where it would read another frame.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "backends/backend.h"
#include "backends/common/atlas.h"
#include "backends/common/layouts.h"
#include "backends/common/view_culling.h"
#include "tests/backend_availability.h"

namespace omnishadow {
namespace {

const std::string kScenes = OMNISHADOW_TEST_SCENES_DIR;

class ManyLightsTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    try {
      backend_ = create_backend(GetParam(), GetParam() == "vulkan"
                                                ? std::map<std::string, std::string>{{"api_checks", "1"}}
                                                : std::map<std::string, std::string>{});
    } catch (const std::exception& e) {
      OMNISHADOW_SKIP_UNAVAILABLE(GetParam(), std::string("cannot bring the backend up: ") + e.what());
    }
    hall_ = scene::load_scene_file(kScenes + "/hall.json");
  }
  void TearDown() override {
    if (!backend_) return;
    const std::vector<std::string> messages = backend_->drain_api_errors();
    EXPECT_TRUE(messages.empty()) << messages.size() << " API message(s), first: " << messages.front();
  }

  CaseConfig hall_case(int lights, Layout layout, Technique t = Technique::six_pass,
                       Filter f = Filter::pcf_disk20, Storage s = Storage::linear_depth) const {
    CaseConfig c;
    c.backend = GetParam();
    c.scene = "hall";
    c.cube_size = 32;
    c.width = 96;
    c.height = 64;
    c.technique = t;
    c.filter = f;
    c.storage = s;
    c.layout = layout;
    c.light_count = lights;
    return c;
  }
  // The mid-hall view walked 16 units back down the hall (Camera::path): at x = 0, -11.3, -16 at frames 0,
  // 94, 188.
  scene::Scene walking_hall() const {
    scene::Scene hall = hall_;
    hall.camera.position = {0.0f, 3.0f, 0.0f};
    hall.camera.target = {20.0f, 2.0f, 0.0f};
    hall.camera.path.amplitude = {-16.0f, 0.0f, 0.0f};
    hall.camera.path.frequency = scene::kSeedLightFrequency;
    return hall;
  }
  // Light k of the hall as a scene of its own: what the many-light case's light k must reproduce.
  scene::Scene alone(int k) const {
    scene::Scene s = hall_;
    s.point_lights = {hall_.point_lights[size_t(k)]};
    return s;
  }

  std::unique_ptr<Backend> backend_;
  scene::Scene hall_;
};

// Four lamps in one texture (a cube-map array, or six layers each of a 2D array), read back light by light:
// each light's map, distances and shadow factor are bit for bit those of the light rendered alone, so no
// light reads or writes another's layers, uniforms or range (the swaying lamps reach 10 units, the others
// 12).
TEST_P(ManyLightsTest, EachLightsLayersHoldWhatItRendersAlone) {
  for (Layout layout : {Layout::cube_array, Layout::face_array})
    for (Filter filter : {Filter::pcf_disk20, Filter::vsm}) {
      const Storage storage = filter == Filter::vsm ? Storage::vsm_moments : Storage::linear_depth;
      if (layout == Layout::face_array && filter == Filter::vsm) continue;  // moments: cube faces only
      CaseConfig many = hall_case(4, layout, Technique::six_pass, filter, storage);
      backend_->load(hall_);
      backend_->configure(many);
      backend_->render(3, FrameKind::check);
      std::vector<Images> lights;
      for (int k = 0; k < 4; ++k) lights.push_back(backend_->read_back(CubeReadBack::full, k));
      for (int k = 0; k < 4; ++k) {
        SCOPED_TRACE(many.id() + ", light " + std::to_string(k));
        backend_->load(alone(k));
        CaseConfig one = many;
        one.light_count = 1;
        backend_->configure(one);
        backend_->render(3, FrameKind::check);
        const Images solo = backend_->read_back(CubeReadBack::full);
        EXPECT_EQ(lights[size_t(k)].light_far, solo.light_far);
        EXPECT_EQ(lights[size_t(k)].light_far, hall_.point_lights[size_t(k)].far_plane);
        for (size_t f = 0; f < 6; ++f) EXPECT_EQ(lights[size_t(k)].cube_distance[f], solo.cube_distance[f]);
        EXPECT_EQ(lights[size_t(k)].moments, solo.moments);
        EXPECT_EQ(lights[size_t(k)].shadow_factor, solo.shadow_factor);
        EXPECT_EQ(lights[size_t(k)].world_position, solo.world_position);
      }
      EXPECT_NE(lights[0].cube_distance[0], lights[1].cube_distance[0]) << "two lamps, two different maps";
      EXPECT_NE(lights[0].shadow_factor, lights[1].shadow_factor);
      EXPECT_EQ(lights[0].lit_rgba8, lights[3].lit_rgba8)
          << "every light's read-back shows the one lit frame";
    }
}

// Every light shades the frame: with four lamps, the lit frame is brighter than with the first alone wherever
// another lamp reaches, and never darker.
TEST_P(ManyLightsTest, TheLitFrameSumsEveryLight) {
  backend_->load(hall_);
  backend_->configure(hall_case(1, Layout::cube_array));
  backend_->render(3, FrameKind::check);
  const Images one = backend_->read_back(CubeReadBack::sampled);
  backend_->configure(hall_case(4, Layout::cube_array));
  backend_->render(3, FrameKind::check);
  const Images four = backend_->read_back(CubeReadBack::sampled);
  ASSERT_EQ(one.lit_rgba8.size(), four.lit_rgba8.size());
  size_t brighter = 0, darker = 0;
  for (size_t i = 0; i < one.lit_rgba8.size(); ++i) {
    brighter += four.lit_rgba8[i] > one.lit_rgba8[i];
    darker += four.lit_rgba8[i] < one.lit_rgba8[i];
  }
  EXPECT_EQ(darker, 0u);
  EXPECT_GT(brighter, one.lit_rgba8.size() / 10);
  EXPECT_EQ(four.lit_rgba8, four.timed_lit_rgba8) << "the timed variant shades the same lights";
}

// An atlas's single pass routes faces by viewport, six_pass through viewport 0: the stored distances within
// 1e-4 of far of six_pass's, and at most 0.1% of shadow factors apart (image_checks.cpp's technique
// allowance).
void expect_within_far_bound(const Images& got, const Images& want, const std::string& what) {
  for (size_t f = 0; f < 6; ++f) {
    ASSERT_EQ(got.cube_distance[f].size(), want.cube_distance[f].size()) << what;
    for (size_t i = 0; i < got.cube_distance[f].size(); ++i)
      ASSERT_LE(std::abs(got.cube_distance[f][i] - want.cube_distance[f][i]), 1e-4 * want.light_far)
          << what << ", face " << f << ", texel " << i;
  }
  size_t differ = 0;
  for (size_t i = 0; i < got.shadow_factor.size(); ++i)
    differ += got.shadow_factor[i] != want.shadow_factor[i];
  EXPECT_LE(double(differ), 0.001 * double(got.shadow_factor.size())) << what;
}

// The single-pass techniques render every light's cube as six_pass does, light by light, and so do vs_layer
// and the geometry shader with every light in one pass (an instance per light and face; invocations routing
// each triangle to the faces of every light it reaches); in an atlas, where a single pass routes each
// face to its tile by viewport, within the bound above, as nv_swizzle is in either layout.
TEST_P(ManyLightsTest, SinglePassTechniquesReproduceSixPassForEveryLight) {
  backend_->load(hall_);
  // Sixteen lamps' records left in the light list first: a one pass that reads past the case's four lights
  // (the list's length() is the buffer's on Vulkan, not the case's) then renders them into the last layers.
  backend_->configure(hall_case(16, Layout::cube_array));
  backend_->render(3, FrameKind::timed);
  for (Layout layout : {Layout::cube_array, Layout::atlas}) {
    // The atlas at 48, whose tiles' viewport scale (24) is no power of two: where the drivers here round
    // apart.
    auto lamps = [&](Technique t) {
      CaseConfig c = hall_case(4, layout, t);
      if (layout == Layout::atlas) c.cube_size = 48;
      return c;
    };
    const CaseConfig reference = lamps(Technique::six_pass);
    backend_->configure(reference);
    backend_->render(3, FrameKind::check);
    std::vector<Images> expected;
    for (int k = 0; k < 4; ++k) expected.push_back(backend_->read_back(CubeReadBack::full, k));
    int compared = 0;
    CaseConfig one_pass = lamps(Technique::vs_layer), one_gs_pass = lamps(Technique::geometry_shader);
    one_pass.light_grouping = one_gs_pass.light_grouping = LightGrouping::all_lights;
    // nv_swizzle through its emulation (Mesa lacks the NV extensions), where the NV extensions are not there
    // to run it natively: its clip coordinates are the swizzled (p - light, near), not the face matrix's
    // product, so it is held to the bound in either layout.
    CaseConfig swizzle = lamps(Technique::nv_swizzle);
    swizzle.emulate_nv_swizzle = !backend_->supports(swizzle).ok;
    for (const CaseConfig& c :
         {lamps(Technique::geometry_shader), lamps(Technique::geometry_shader_instanced),
          lamps(Technique::vs_layer), one_pass, one_gs_pass, swizzle}) {
      if (!backend_->supports(c).ok) continue;
      backend_->configure(c);
      backend_->render(3, FrameKind::check);
      for (int k = 0; k < 4; ++k) {
        const Images got = backend_->read_back(CubeReadBack::full, k);
        if (layout == Layout::atlas || c.technique == Technique::nv_swizzle) {  // image_checks.cpp's bound
          expect_within_far_bound(got, expected[size_t(k)], c.id() + ", light " + std::to_string(k));
          continue;
        }
        for (size_t f = 0; f < 6; ++f)
          EXPECT_EQ(got.cube_distance[f], expected[size_t(k)].cube_distance[f]) << c.id();
        EXPECT_EQ(got.shadow_factor, expected[size_t(k)].shadow_factor) << c.id() << ", light " << k;
      }
      ++compared;
    }
    EXPECT_GT(compared, 0) << "no single-pass technique on " << GetParam() << " in " << to_string(layout);
    EXPECT_TRUE(backend_->supports(swizzle).ok) << "nv_swizzle (native or emulated) in " << to_string(layout)
                                                << ": " << backend_->supports(swizzle).reason;
    if (layout == Layout::cube_array) {
      EXPECT_EQ(backend_->supports(one_pass).ok, backend_->supports(lamps(Technique::vs_layer)).ok)
          << "every light in one pass wherever vs_layer renders: " << backend_->supports(one_pass).reason;
      EXPECT_EQ(backend_->supports(one_gs_pass).ok, backend_->supports(lamps(Technique::geometry_shader)).ok)
          << "and wherever the geometry shader renders: " << backend_->supports(one_gs_pass).reason;
    }
  }
}

// mesh_shader, native where the device has mesh shading and through its emulation elsewhere (the task stage
// as a compute shader, the mesh stage as a vertex shader: the same task body and functions), per light with
// and without its meshlet culling and every light in one pass (a task workgroup per meshlet group and light,
// culled per light and face): bit for bit six_pass's, light by light, in both layouts that hold several
// lights' cubes. At frame 12 the hall's rollers and carts have left where load() built their meshlet spheres:
// culling by the spheres at rest drops faces the casters now reach.
TEST_P(ManyLightsTest, MeshShaderRoutesEveryLightWhereTheCastersAreNow) {
  backend_->load(hall_);
  constexpr int kFrame = 12;
  for (Layout layout : {Layout::cube_array, Layout::cube}) {
    const CaseConfig reference = hall_case(4, layout, Technique::six_pass, Filter::hard);
    backend_->configure(reference);
    backend_->render(kFrame, FrameKind::check);
    std::vector<Images> expected;
    for (int k = 0; k < 4; ++k) expected.push_back(backend_->read_back(CubeReadBack::full, k));
    CaseConfig per_light = hall_case(4, layout, Technique::mesh_shader, Filter::hard);
    per_light.emulate_mesh_shader = !backend_->supports(per_light).ok;
    CaseConfig culled = per_light, one_pass = per_light;
    culled.optimizations.face_culling = true;
    one_pass.light_grouping = LightGrouping::all_lights;
    for (const CaseConfig& c : {per_light, culled, one_pass}) {
      ASSERT_TRUE(backend_->supports(c).ok) << c.id() << ": " << backend_->supports(c).reason;
      backend_->configure(c);
      backend_->render(kFrame, FrameKind::check);
      for (int k = 0; k < 4; ++k) {
        const Images got = backend_->read_back(CubeReadBack::full, k);
        for (size_t f = 0; f < 6; ++f)
          EXPECT_EQ(got.cube_distance[f], expected[size_t(k)].cube_distance[f])
              << c.id() << ", light " << k << ", face " << f;
        EXPECT_EQ(got.shadow_factor, expected[size_t(k)].shadow_factor) << c.id() << ", light " << k;
      }
    }
  }
}

// nv_swizzle's reversed depth has no far plane (viewport_swizzle.h): with r32f_distance, a lamp whose range
// ends inside the hall would store the walls beyond it where six_pass's far plane clips them (62 units in a
// lamp's +X face whose far is 12), unless the fragment stage drops them. Held to six_pass within the bound,
// in both layouts that route faces by layer and by viewport.
TEST_P(ManyLightsTest, NvSwizzleStoresNothingBeyondARangeThatEndsInsideTheScene) {
  backend_->load(hall_);
  for (Layout layout : {Layout::cube_array, Layout::atlas}) {
    const CaseConfig six = hall_case(4, layout, Technique::six_pass, Filter::hard, Storage::r32f_distance);
    CaseConfig swizzle = hall_case(4, layout, Technique::nv_swizzle, Filter::hard, Storage::r32f_distance);
    swizzle.emulate_nv_swizzle = !backend_->supports(swizzle).ok;
    ASSERT_TRUE(backend_->supports(swizzle).ok) << backend_->supports(swizzle).reason;
    std::vector<Images> want;
    backend_->configure(six);
    backend_->render(3, FrameKind::check);
    for (int k = 0; k < 4; ++k) want.push_back(backend_->read_back(CubeReadBack::full, k));
    backend_->configure(swizzle);
    backend_->render(3, FrameKind::check);
    for (int k = 0; k < 4; ++k)
      expect_within_far_bound(backend_->read_back(CubeReadBack::full, k), want[size_t(k)],
                              swizzle.id() + ", light " + std::to_string(k));
  }
}

// Layout cube with several lights (a cube and a sampler per light, the lighting pass's array indexed by the
// light) samples the very texels cube_array does, through the same seamless cube filtering: the same lit
// image and shadow factor bit for bit, at 16 lamps (every element of the array read) with a NEAREST, a LINEAR
// moments and a compare filter. One lamp more, or clustered lists (a per-pixel index), is refused with the
// reason.
TEST_P(ManyLightsTest, ACubePerLightSamplesWhatTheCubeArrayDoes) {
  backend_->load(hall_);
  for (const auto& [filter, storage] : {std::pair{Filter::pcf_disk20, Storage::linear_depth},
                                        {Filter::vsm, Storage::vsm_moments},
                                        {Filter::hw_compare2x2, Storage::linear_depth}}) {
    const CaseConfig cubes = hall_case(16, Layout::cube, Technique::six_pass, filter, storage);
    const CaseConfig array = hall_case(16, Layout::cube_array, Technique::six_pass, filter, storage);
    if (!backend_->supports(array).ok) continue;  // lavapipe: no linear filtering of D32 (hw_compare2x2)
    ASSERT_TRUE(backend_->supports(cubes).ok) << cubes.id() << ": " << backend_->supports(cubes).reason;
    backend_->configure(array);
    backend_->render(3, FrameKind::check);
    const Images want = backend_->read_back(CubeReadBack::sampled, 15);
    backend_->configure(cubes);
    backend_->render(3, FrameKind::check);
    const Images got = backend_->read_back(CubeReadBack::sampled, 15);
    EXPECT_EQ(got.lit_rgba8, want.lit_rgba8) << cubes.id();
    EXPECT_EQ(got.shadow_factor, want.shadow_factor) << cubes.id();
  }
  CaseConfig too_many = hall_case(kLightCubes + 1, Layout::cube);
  EXPECT_NE(backend_->supports(too_many).reason.find("16 at most"), std::string::npos)
      << backend_->supports(too_many).reason;
  CaseConfig clustered = hall_case(4, Layout::cube);
  clustered.optimizations.light_clusters = true;
  EXPECT_NE(backend_->supports(clustered).reason.find("dynamically uniform"), std::string::npos)
      << backend_->supports(clustered).reason;
}

// Reading another light back re-renders the check frame's lighting: refused once another frame was rendered,
// and for a light the case does not have.
TEST_P(ManyLightsTest, AnotherLightIsReadBackFromTheCheckFrameOnly) {
  backend_->load(hall_);
  backend_->configure(hall_case(4, Layout::cube_array));
  backend_->render(3, FrameKind::check);
  EXPECT_NO_THROW(backend_->read_back(CubeReadBack::sampled, 2));
  EXPECT_THROW(backend_->read_back(CubeReadBack::sampled, 4), std::logic_error);
  backend_->render(4, FrameKind::timed);
  EXPECT_THROW(backend_->read_back(CubeReadBack::sampled, 1), std::logic_error);
  EXPECT_NO_THROW(backend_->read_back(CubeReadBack::sampled, 2)) << "the light last reported reads back";
}

// Culling to the view (--optimize view) with the camera mid-hall, looking down it: lamps behind it get no
// pass and faces no visible point reads get none, yet the lit frame, every light's shadow factor and every
// face drawn are bit for bit those without it, at the first frame after configure (culled faces cleared) and
// at the next (out-of-view lights and culled faces skipped, left as they were), with less shadow work.
TEST_P(ManyLightsTest, ViewCullingChangesNothingTheFrameReads) {
  scene::Scene hall = hall_;
  hall.camera.position = {0.0f, 3.0f, 0.0f};
  hall.camera.target = {20.0f, 2.0f, 0.0f};
  backend_->load(hall);
  const int lights = 16, frame = 3;
  for (Technique t : {Technique::six_pass, Technique::geometry_shader, Technique::geometry_shader_instanced,
                      Technique::vs_layer}) {
    CaseConfig off = hall_case(lights, Layout::cube_array, t);
    if (!backend_->supports(off).ok) continue;
    CaseConfig on = off;
    on.optimizations.view_culling = true;
    ASSERT_TRUE(backend_->supports(on).ok) << backend_->supports(on).reason;
    backend_->configure(off);
    backend_->render(frame, FrameKind::check);
    std::vector<Images> want;
    for (int k = 0; k < lights; ++k) want.push_back(backend_->read_back(CubeReadBack::full, k));
    const FrameCounters work_off = backend_->count_work(frame);
    backend_->configure(on);
    int out_of_view = 0, partial = 0;
    for (int repeat = 0; repeat < 2; ++repeat) {
      backend_->render(frame, FrameKind::check);
      for (int k = 0; k < lights; ++k) {
        SCOPED_TRACE(on.id() + ", light " + std::to_string(k) + ", frame " + std::to_string(repeat));
        const Images got = backend_->read_back(CubeReadBack::full, k);
        scene::FocusLight focus(hall, k);
        const uint8_t faces = gpu::view_faces(hall, on, frame, got.light_far, got.cube_size);
        out_of_view += repeat == 0 && faces == 0;
        partial += repeat == 0 && faces != 0 && faces != cube::kAllFaces;
        for (int f = 0; f < 6; ++f) {
          if (!(faces >> f & 1)) continue;  // culled: cleared, or as the frame before left it
          EXPECT_EQ(got.cube_distance[size_t(f)], want[size_t(k)].cube_distance[size_t(f)]);
        }
        EXPECT_EQ(got.shadow_factor, want[size_t(k)].shadow_factor);
        EXPECT_EQ(got.lit_rgba8, want[size_t(k)].lit_rgba8);
      }
    }
    EXPECT_GT(out_of_view, 0) << "lamps behind the camera";
    EXPECT_GT(partial, 0) << "lamps beside it, some faces turned away from the view";
    const FrameCounters work_on = backend_->count_work(frame);
    if (work_on.shadow.valid && work_off.shadow.valid) {
      EXPECT_LT(work_on.shadow.primitives_submitted + work_on.shadow.gs_primitives,
                work_off.shadow.primitives_submitted + work_off.shadow.gs_primitives)
          << to_string(t);
    }
  }
}

// The same view walked 16 units back down the hall (Camera::path) over frames rendered in turn: lamps behind
// it at rest come before it, so the faces culled and the clustered lists change from frame to frame, and at
// each frame the lit image is bit for bit the one without culling or lists.
TEST_P(ManyLightsTest, CullingAndClustersFollowAWalkingCamera) {
  scene::Scene hall = walking_hall();
  backend_->load(hall);
  const int lights = 16;
  const std::vector<int> frames = {0, 94, 188};  // the camera at x = 0, -11.3, -16
  const CaseConfig off = hall_case(lights, Layout::cube_array);
  CaseConfig on = off;
  on.optimizations.view_culling = true;
  on.optimizations.light_clusters = true;
  ASSERT_TRUE(backend_->supports(on).ok) << backend_->supports(on).reason;
  backend_->configure(off);
  std::vector<Images> want;
  for (int frame : frames) {
    backend_->render(frame, FrameKind::check);
    want.push_back(backend_->read_back(CubeReadBack::sampled, 0));
  }
  backend_->configure(on);
  std::vector<int> in_view;
  for (size_t i = 0; i < frames.size(); ++i) {
    SCOPED_TRACE("frame " + std::to_string(frames[i]));
    backend_->render(frames[i], FrameKind::check);
    const Images got = backend_->read_back(CubeReadBack::sampled, 0);
    EXPECT_EQ(got.lit_rgba8, want[i].lit_rgba8);
    EXPECT_EQ(got.shadow_factor, want[i].shadow_factor);
    int seen = 0;
    for (int k = 0; k < lights; ++k) {
      scene::FocusLight focus(hall, k);
      seen += gpu::view_faces(hall, on, frames[i], hall.light().far_plane, off.cube_size) != 0;
    }
    in_view.push_back(seen);
  }
  EXPECT_LT(in_view.front(), in_view.back()) << "the walk brings lamps into view";
}

// The walk again, with an atlas whose tiles are planned again every frame by distance (--atlas-replan 1)
// and static caching, the rollers and carts held still so that the cache keeps what a re-plan leaves in
// place: frames rendered in turn must light the scene bit for bit as a fresh start at each frame does. The
// lamps that stand still keep their maps where their blocks stay, and render again where a re-plan moved
// them; the read-back follows the frame's tiles.
TEST_P(ManyLightsTest, AnAtlasReplannedOnAWalkRendersTheLightsItMoves) {
  scene::Scene hall = walking_hall();
  for (scene::Object& o : hall.objects) o.motion.amplitude = glm::vec3(0.0f);
  ASSERT_FALSE(hall.has_moving_objects());
  backend_->load(hall);
  CaseConfig c = hall_case(24, Layout::atlas);  // lamps 16-23 stand still
  c.atlas_tiles = AtlasTiles::by_distance;
  c.atlas_replan_frames = 1;
  c.optimizations.static_cache = true;
  ASSERT_TRUE(backend_->supports(c).ok) << backend_->supports(c).reason;
  const std::vector<int> frames = {0, 47, 94, 141, 188};
  std::vector<Images> fresh;
  for (int frame : frames) {
    backend_->configure(c);
    backend_->render(frame, FrameKind::check);
    fresh.push_back(backend_->read_back(CubeReadBack::sampled, 0));
  }
  backend_->configure(c);
  int still_moved = 0, still_kept = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    SCOPED_TRACE("frame " + std::to_string(frames[i]));
    backend_->render(frames[i], FrameKind::check);
    const Images got = backend_->read_back(CubeReadBack::sampled, 0);
    EXPECT_EQ(got.lit_rgba8, fresh[i].lit_rgba8);
    EXPECT_EQ(got.shadow_factor, fresh[i].shadow_factor);
    const atlas::Plan now = atlas::plan_at(c, hall, frames[i]);
    EXPECT_EQ(got.cube_size, now.lights[0].face_size) << "light 0 read back at the frame's tiles";
    if (i == 0) continue;
    const atlas::Plan was = atlas::plan_at(c, hall, frames[i - 1]);
    for (size_t k = 16; k < now.lights.size(); ++k) {
      const bool moved = was.lights[k].x != now.lights[k].x || was.lights[k].y != now.lights[k].y ||
                         was.lights[k].face_size != now.lights[k].face_size;
      (moved ? still_moved : still_kept) += 1;
    }
  }
  EXPECT_GT(still_moved, 0) << "the walk moves a still lamp's block";
  EXPECT_GT(still_kept, 0) << "and keeps one's";
}

// --raster-perturb moves each target by its own sub-pixel steps: an atlas tile a quarter of --cube moves as a
// cube of the tile's size does under the same steps, not by a quarter of them (the step is scaled by the
// light's FrameUniforms::raster_knobs). A step of one whole texel, so that the two sides differ at every
// silhouette and along every slope: the tile matches the cube moved by the same steps, and not the cube moved
// by a quarter of them (what an unscaled step would give). Matching allows a few texels whose edges the
// viewport's offset rounds apart (the drivers here: 1 and 5 of 12288).
TEST_P(ManyLightsTest, APerturbedAtlasTileMovesByItsOwnSteps) {
  backend_->load(hall_);
  CaseConfig atlas = hall_case(24, Layout::atlas, Technique::six_pass, Filter::hard);
  atlas.cube_size = 64;
  atlas.atlas_tiles = AtlasTiles::by_distance;
  const float steps = std::ldexp(1.0f, backend_->device().subpixel_bits);  // one texel of the target
  atlas.raster_perturb_steps = steps;
  const atlas::Plan plan = atlas::plan_for(atlas, hall_);
  std::vector<int> quarter;  // the lamps whose faces are a quarter of --cube
  for (size_t k = 0; k < plan.lights.size(); ++k)
    if (plan.lights[k].face_size * 4 == atlas.cube_size) quarter.push_back(int(k));
  ASSERT_FALSE(quarter.empty()) << "the hall's far lamps get 16-texel tiles at --cube 64";
  ASSERT_TRUE(backend_->supports(atlas).ok) << backend_->supports(atlas).reason;
  backend_->configure(atlas);
  backend_->render(3, FrameKind::check);
  std::vector<Images> tiles;
  for (int k : quarter) tiles.push_back(backend_->read_back(CubeReadBack::full, k));
  auto differing = [&](float cube_steps) {
    CaseConfig cubes = hall_case(24, Layout::cube_array, Technique::six_pass, Filter::hard);
    cubes.cube_size = atlas.cube_size / 4;
    cubes.raster_perturb_steps = cube_steps;
    backend_->configure(cubes);
    backend_->render(3, FrameKind::check);
    size_t beyond = 0, texels = 0;
    for (size_t i = 0; i < quarter.size(); ++i) {
      const Images want = backend_->read_back(CubeReadBack::full, quarter[i]);
      for (size_t f = 0; f < 6; ++f) {
        EXPECT_EQ(tiles[i].cube_distance[f].size(), want.cube_distance[f].size());
        for (size_t t = 0; t < want.cube_distance[f].size() && t < tiles[i].cube_distance[f].size(); ++t)
          beyond += std::abs(tiles[i].cube_distance[f][t] - want.cube_distance[f][t]) > 1e-4 * want.light_far;
        texels += want.cube_distance[f].size();
      }
    }
    std::printf("%s: %zu of %zu texels of %zu lamps beyond 1e-4 of far from the cube moved by %g steps\n",
                atlas.id().c_str(), beyond, texels, quarter.size(), double(cube_steps));
    return double(beyond) / double(texels);
  };
  EXPECT_LE(differing(steps), 0.002) << "the tile moves as a cube of its size under the same steps";
  EXPECT_GT(differing(steps / 4.0f), 0.05) << "and not by a quarter of them";
}

TEST_P(ManyLightsTest, LayoutCubeSaysWhyItHoldsSixteenLightsAtMost) {
  EXPECT_TRUE(backend_->supports(hall_case(kLightCubes, Layout::cube)).ok)
      << backend_->supports(hall_case(kLightCubes, Layout::cube)).reason;
  const Support s = backend_->supports(hall_case(64, Layout::cube));
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.reason.find("cube_array"), std::string::npos) << s.reason;
  EXPECT_TRUE(backend_->supports(hall_case(64, Layout::cube_array)).ok);
}

INSTANTIATE_TEST_SUITE_P(Api, ManyLightsTest, ::testing::Values("gl", "vulkan"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace omnishadow
