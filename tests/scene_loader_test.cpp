// Scene files: the tutorials' scenes load as the tutorials describe them, and every malformed form is an
// error that names the file and the JSON pointer of the offending field.

#include <gtest/gtest.h>

#include <cmath>

#include "scenes/scene.h"

namespace omnishadow::scene {
namespace {

const std::string kScenes = OMNISHADOW_TEST_SCENES_DIR;

TEST(SceneLoader, RoomIsTheSeedScene) {
  Scene s = load_scene_file(kScenes + "/room.json");
  EXPECT_EQ(s.name, "room");
  ASSERT_EQ(s.objects.size(), 6u);
  EXPECT_EQ(s.triangle_count(), 72u);
  // The room: a [-1,1] cube scaled 5, normals pointing inwards, never back-face culled.
  EXPECT_EQ(s.objects[0].bounds_min, glm::vec3(-5));
  EXPECT_EQ(s.objects[0].bounds_max, glm::vec3(5));
  EXPECT_FALSE(s.objects[0].cull_back_faces);
  for (uint32_t i = 0; i < s.objects[0].vertex_count; ++i) {
    const Vertex& v = s.vertices[i];
    EXPECT_LT(glm::dot(v.normal, v.position), 0.0f) << "room normals must face inwards";
  }
  // cube1: T(4,-3.5,0) S0.5.
  EXPECT_EQ(s.objects[1].bounds_min, glm::vec3(3.5f, -4.0f, -0.5f));
  EXPECT_EQ(s.objects[1].bounds_max, glm::vec3(4.5f, -3.0f, 0.5f));
  EXPECT_TRUE(s.objects[1].cull_back_faces);
  // cube5 is rotated 60 degrees about normalize(1,0,1): its bounds exceed the unrotated 0.75 half-size.
  glm::vec3 half = (s.objects[5].bounds_max - s.objects[5].bounds_min) * 0.5f;
  EXPECT_GT(half.y, 0.8f);
  EXPECT_NEAR((s.objects[5].bounds_max.y + s.objects[5].bounds_min.y) * 0.5f, 2.0f, 1e-5);
  // The light: near 1, far 25; at the origin on frame 0, z = 3 sin(0.5 t) after that.
  EXPECT_EQ(s.light().near_plane, 1.0f);
  EXPECT_EQ(s.light().far_plane, 25.0f);
  EXPECT_EQ(s.light().path.at(0), glm::vec3(0));
  glm::vec3 p = s.light().path.at(120);  // t = 2 s at 60 frames per second
  EXPECT_NEAR(p.z, 3.0f * std::sin(1.0f), 1e-4);
  EXPECT_EQ(s.camera.position, glm::vec3(0, 0, 3));
  EXPECT_EQ(s.camera.width, 800);
  EXPECT_EQ(s.camera.height, 600);
}

TEST(SceneLoader, OgldevAndHeavyLoad) {
  Scene o = load_scene_file(kScenes + "/ogldev.json");
  EXPECT_EQ(o.objects.size(), 4u);
  EXPECT_EQ(o.light().path.at(77), glm::vec3(0, 5, 0));
  EXPECT_EQ(o.light().far_plane, 100.0f);
  Scene h = load_scene_file(kScenes + "/heavy.json");
  EXPECT_GE(h.triangle_count(), 100000u);
}

TEST(SceneLoader, NormalsAreUnitAndTrianglesCounterClockwiseFromTheLitSide) {
  Scene s = load_scene_file(kScenes + "/ogldev.json");
  for (size_t i = 0; i < s.vertices.size(); i += 3) {
    const Vertex &a = s.vertices[i], &b = s.vertices[i + 1], &c = s.vertices[i + 2];
    glm::vec3 face_normal = glm::cross(b.position - a.position, c.position - a.position);
    if (glm::length(face_normal) < 1e-9f) continue;
    EXPECT_NEAR(glm::length(a.normal), 1.0f, 1e-4);
    EXPECT_GT(glm::dot(face_normal, a.normal + b.normal + c.normal), 0.0f) << "triangle " << i / 3;
  }
}

struct BadScene {
  const char* text;
  const char* expected;  // a substring of the one-line error
};

class SceneLoaderErrors : public ::testing::TestWithParam<BadScene> {};

TEST_P(SceneLoaderErrors, NameFileAndPointer) {
  const BadScene& bad = GetParam();
  try {
    load_scene_text(bad.text, "scenes/bad.json");
    FAIL() << "accepted: " << bad.text;
  } catch (const SceneError& e) {
    std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << "error must be one line: " << what;
    EXPECT_EQ(what.rfind("scenes/bad.json: ", 0), 0u) << what;
    EXPECT_NE(what.find(bad.expected), std::string::npos) << "expected '" << bad.expected << "' in: " << what;
  }
}

#define LIGHT R"("light": {"position": [0, 0, 0]})"
INSTANTIATE_TEST_SUITE_P(
    Malformed, SceneLoaderErrors,
    ::testing::Values(
        BadScene{"{", "malformed JSON"}, BadScene{"", "malformed JSON"},
        BadScene{"[1, 2]", "/: expected an object"},
        BadScene{R"({"objects": [{"type": "box"}]})", "/light: missing required field"},
        BadScene{"{" LIGHT "}", "/objects: missing required field"},
        BadScene{"{" LIGHT R"(, "objects": []})", "/objects: a scene needs at least one object"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "teapot"}]})",
                 "/objects/0/type: unknown object type 'teapot'"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box"}, {"type": "box", "scale": 0}]})",
                 "/objects/1/scale: scale must be > 0"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box", "scale": [1, -2, 1]}]})", "/objects/0/scale"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box", "translate": [1, 2]}]})",
                 "/objects/0/translate: expected an array of 3 numbers"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box", "translate": [1, "x", 2]}]})",
                 "/objects/0/translate/1: expected a number"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box", "translate": [1e300, 0, 0]}]})",
                 "/objects/0/translate/0: number must be finite"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box", "sclae": 2}]})",
                 "/objects/0/sclae: unknown field"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box", "rotate": {"degrees": 30, "axis": [0, 0, 0]}}]})",
                 "/objects/0/rotate/axis: axis must not be zero"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "sphere", "segments": [2, 8]}]})",
                 "/objects/0/segments/0"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "obj", "file": "missing.obj"}]})",
                 "/objects/0/file: cannot open OBJ file"},
        BadScene{R"({"light": {"near": 5, "far": 1}, "objects": [{"type": "box"}]})",
                 "/light/far: far must be greater than near"},
        BadScene{R"({"light": {"type": "spot"}, "objects": [{"type": "box"}]})", "/light/type"},
        BadScene{R"({"format": "other/2", )" LIGHT R"(, "objects": [{"type": "box"}]})",
                 "/format: unsupported"},
        BadScene{"{" LIGHT R"(, "camera": {"size": [0, 600]}, "objects": [{"type": "box"}]})",
                 "/camera/size/0: must be an integer in [1, 16384]"},
        BadScene{"{" LIGHT
                 R"(, "objects": [{"type": "box", "array": {"count": [2000, 1, 1], "spacing": [1, 0, 0]}}]})",
                 "/objects/0/array/count/0"},
        // Found by the fuzzer: a number beyond double escaped as nlohmann's out_of_range.
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box", "translate": [1e999, 0, 0]}]})",
                 "malformed JSON"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box", "scale": 1e-40}]})",
                 "/objects/0: transform gives non-finite"},
        BadScene{"{" LIGHT R"(, "camera": {"position": [0, 5, 0], "target": [0, 0, 0], "up": [0, 1, 0]},
                 "objects": [{"type": "box"}]})",
                 "/camera/up: up must not be zero or parallel"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "obj", "file": "/proc"}]})",
                 "/objects/0/file: cannot open OBJ file"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "sphere", "segments": [4096, 4096]}]})",
                 "/objects/0/segments/0"},
        // Several lights: each checked where it stands.
        BadScene{R"({"lights": [{"type": "point", "path": {"phase": 1e9}}], "objects": [{"type": "box"}]})",
                 "/lights/0/path/phase: must be in [-1000, 1000]"},
        BadScene{R"({"lights": [{"type": "area"}], "objects": [{"type": "box"}]})",
                 "/lights/0/type: unknown light type"},
        BadScene{
            R"({"lights": [{"type": "directional", "direction": [0, 0, 0]}], "objects": [{"type": "box"}]})",
            "/lights/0/direction: direction must not be zero"},
        BadScene{R"({"lights": [{"type": "spot", "direction": [0, -1, 0], "cone_degrees": 180}],
                 "objects": [{"type": "box"}]})",
                 "/lights/0/cone_degrees"},
        BadScene{
            R"({"lights": [{"type": "directional", "direction": [0, -1, 0], "near": 1}], "objects": [{"type": "box"}]})",
            "/lights/0/near: unknown field"},
        BadScene{R"({"light": {}, "lights": [{"type": "point"}], "objects": [{"type": "box"}]})",
                 "/lights: give \"light\" or \"lights\", not both"},
        BadScene{R"({"lights": [], "objects": [{"type": "box"}]})", "/lights: expected a non-empty array"},
        BadScene{
            R"({"lights": [{"type": "spot", "direction": [0, -1, 0]}, {"type": "spot", "direction": [0, -1, 0]},
                 {"type": "spot", "direction": [0, -1, 0]}, {"type": "spot", "direction": [0, -1, 0]},
                 {"type": "directional", "direction": [0, -1, 0]}], "objects": [{"type": "box"}]})",
            "/lights/4: at most 4 spot/directional lights"},
        // Moving casters: a path as a light's, without a position.
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box", "path": {"amplitude": [1, 0]}}]})",
                 "/objects/0/path/amplitude: expected an array of 3 numbers"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box", "path": {"position": [1, 0, 0]}}]})",
                 "/objects/0/path/position: unknown field"},
        BadScene{"{" LIGHT R"(, "objects": [{"type": "box", "path": {"frequency": "fast"}}]})",
                 "/objects/0/path/frequency: expected a number"},
        // A walking camera: the same path, its position and target moved together.
        BadScene{"{" LIGHT R"(, "camera": {"path": {"amplitude": [1, 0]}}, "objects": [{"type": "box"}]})",
                 "/camera/path/amplitude: expected an array of 3 numbers"},
        BadScene{"{" LIGHT R"(, "camera": {"path": {"target": [1, 0, 0]}}, "objects": [{"type": "box"}]})",
                 "/camera/path/target: unknown field"}),
    [](const ::testing::TestParamInfo<BadScene>& info) { return "case" + std::to_string(info.index); });

TEST(SceneLoader, LightsEachGetWhatTheyNeed) {
  Scene s = load_scene_file(std::string(OMNISHADOW_TEST_SCENES_DIR) + "/mixed.json");
  EXPECT_TRUE(s.has_point_light());
  ASSERT_EQ(s.map_lights.size(), 2u);
  EXPECT_EQ(s.map_lights[0].type, MapLightType::spot);
  EXPECT_EQ(s.map_lights[1].type, MapLightType::directional);
  EXPECT_NEAR(glm::length(s.map_lights[1].direction), 1.0f, 1e-6f);
  Scene d = load_scene_file(std::string(OMNISHADOW_TEST_SCENES_DIR) + "/seed003.json");
  EXPECT_FALSE(d.has_point_light());
  ASSERT_EQ(d.map_lights.size(), 1u);
  EXPECT_TRUE(d.map_lights[0].cull_front_faces);
}

// Many point lights: file order kept (a case renders the first K), each with its own path and phase; more
// than the cap is an error naming the first one over; --light moves the first and no other.
TEST(SceneLoader, ManyPointLightsKeepTheirOrderAndPaths) {
  const std::string hall_path = std::string(OMNISHADOW_TEST_SCENES_DIR) + "/hall.json";
  const Scene hall = load_scene_file(hall_path);
  ASSERT_EQ(hall.point_lights.size(), 64u);
  EXPECT_EQ(hall.light().path.base, glm::vec3(-30.0f, 5.5f, -4.5f));
  EXPECT_EQ(hall.point_lights[2].far_plane, 12.0f);
  EXPECT_EQ(hall.point_lights[3].far_plane, 10.0f) << "the swaying lamps reach less far";
  const LightPath& swaying = hall.point_lights[3].path;
  EXPECT_EQ(swaying.at(0), swaying.base + swaying.amplitude * std::sin(swaying.phase));
  EXPECT_NE(swaying.phase, hall.point_lights[7].path.phase) << "lamps sway out of step";
  LoadOptions moved;
  moved.light = LightPlacement{{1, 2, 3}, {0, 0, 0}};
  const Scene m = load_scene_file(hall_path, moved);
  EXPECT_EQ(m.light().path.base, glm::vec3(1, 2, 3));
  for (size_t i = 1; i < hall.point_lights.size(); ++i) EXPECT_EQ(m.point_lights[i], hall.point_lights[i]);

  std::string many = R"({"objects": [{"type": "box"}], "lights": [)";
  for (int i = 0; i <= kMaxPointLights; ++i) many += std::string(i ? "," : "") + R"({"type": "point"})";
  try {
    load_scene_text(many + "]}", "many.json");
    ADD_FAILURE() << "more point lights than kMaxPointLights were accepted";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(), ("many.json: /lights/" + std::to_string(kMaxPointLights) + ": at most " +
                            std::to_string(kMaxPointLights) + " point lights per scene")
                               .c_str());
  }
}

// The hall's rollers and carts: each array moves as one, by its path's offset from where the file put it, and
// a pose depends on its frame alone (never on the frames posed before it), bounds included.
TEST(SceneLoader, MovingCastersArePosedByTheFrameAlone) {
  Scene hall = load_scene_file(std::string(OMNISHADOW_TEST_SCENES_DIR) + "/hall.json");
  ASSERT_TRUE(hall.has_moving_objects());
  std::vector<size_t> moving;
  for (size_t i = 0; i < hall.objects.size(); ++i)
    if (hall.objects[i].moves()) moving.push_back(i);
  ASSERT_EQ(moving.size(), 7u) << "four rollers and three carts";
  const std::vector<Vertex> rest = hall.vertices;
  const Object& roller = hall.objects[moving[0]];
  EXPECT_EQ(roller.motion.amplitude, glm::vec3(6, 0, 0));
  hall.pose(40);
  const std::vector<Vertex> at40 = hall.vertices;
  const glm::vec3 offset = roller.offset_at(40);
  EXPECT_NE(offset, glm::vec3(0.0f));
  EXPECT_EQ(at40[roller.first_vertex].position, rest[roller.first_vertex].position + offset);
  EXPECT_EQ(roller.bounds_min, roller.rest_bounds_min + offset);
  EXPECT_EQ(roller.bounds_min_at(7), roller.rest_bounds_min + roller.offset_at(7)) << "any frame, any pose";
  for (size_t i = 0; i < hall.objects.size(); ++i)
    if (!hall.objects[i].moves()) {
      const Object& o = hall.objects[i];
      EXPECT_EQ(at40[o.first_vertex].position, rest[o.first_vertex].position) << o.name << " stands still";
    }
  for (int frame : {3, 17, 40}) hall.pose(frame);
  for (size_t v = 0; v < rest.size(); ++v)
    ASSERT_EQ(hall.vertices[v].position, at40[v].position)
        << "vertex " << v << ": frame 40 again, bit for bit";
  hall.put_at_rest();
  EXPECT_EQ(hall.posed_frame, -1);
  for (size_t v = 0; v < rest.size(); ++v) ASSERT_EQ(hall.vertices[v].position, rest[v].position);
  const Scene room = load_scene_file(std::string(OMNISHADOW_TEST_SCENES_DIR) + "/room.json");
  EXPECT_FALSE(room.has_moving_objects());
}

// The camera's path from the file, and --camera's sway on a scene file and on a model (scaled with it, its
// far plane widened by the sway).
TEST(SceneLoader, ACameraWalksByItsPathOrByCameraPlacement) {
  const Scene s = load_scene_text("{" LIGHT R"(, "camera": {"position": [0, 1, 5], "target": [0, 1, 0],
      "path": {"amplitude": [2, 0, 0], "frequency": 1.5, "phase": 0.5}}, "objects": [{"type": "box"}]})",
                                  "walk.json");
  EXPECT_TRUE(s.camera.moves());
  EXPECT_EQ(s.camera.path.amplitude, glm::vec3(2, 0, 0));
  EXPECT_EQ(s.camera.path.frequency, 1.5f);
  EXPECT_EQ(s.camera.at(30).position, glm::vec3(0, 1, 5) + glm::vec3(2, 0, 0) * std::sin(1.5f * 0.5f + 0.5f));
  LoadOptions still;
  still.camera = CameraPlacement{{0, 2, 6}, std::nullopt, glm::vec3(0.0f)};
  const Scene placed = load_scene_file(kScenes + "/hall.json", still);
  EXPECT_FALSE(placed.camera.moves()) << "--camera without a sway stands still";
  EXPECT_EQ(placed.camera.at(100).position, glm::vec3(0, 2, 6));
  LoadOptions swaying = still;
  swaying.camera->amplitude = {4, 0, 0};
  const Scene walked = load_scene_file(kScenes + "/hall.json", swaying);
  EXPECT_EQ(walked.camera.path.amplitude, glm::vec3(4, 0, 0));
  EXPECT_EQ(walked.camera.path.frequency, kSeedLightFrequency);
  const std::string model = kScenes + "/extremes/degenerate.obj";
  const Scene model_still = load_scene_file(model, still);
  const Scene model_walked = load_scene_file(model, swaying);
  EXPECT_TRUE(model_walked.camera.moves());
  EXPECT_FALSE(model_still.camera.moves());
  EXPECT_GT(model_walked.camera.far_plane, model_still.camera.far_plane) << "the far plane takes in the sway";
}

TEST(SceneLoader, MissingFileIsAnError) {
  EXPECT_THROW(load_scene_file("/nonexistent/scene.json"), SceneError);
}

}  // namespace
}  // namespace omnishadow::scene
