// A model run as a scene (scenes/model_scene.h): the placement rule's promises (scale, a light outside the
// model, a far plane holding everything, a camera framing the model), --light / --camera in the file's units,
// and the same overrides on scene files; third-party models from Debian packages (GTEST_SKIP with the reason
// when absent).

#include "scenes/model_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "scenes/scene.h"

namespace omnishadow::scene {
namespace {

const std::string kBunny = "/usr/share/glmark2/models/bunny.obj";
const std::string kEngine = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";

std::string write_file(const std::string& name, const std::string& text) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "omnishadow_model_scene_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

// Every promise of the rule, for a scene built by load_model_scene (world units).
void expect_rule_holds(const Scene& s) {
  ASSERT_EQ(s.objects.size(), 2u);
  const Object& model = s.objects[0];
  const Object& floor = s.objects[1];
  EXPECT_EQ(floor.name, "floor");
  const glm::vec3 c = 0.5f * (model.bounds_min + model.bounds_max);
  EXPECT_NEAR(0.5f * glm::length(model.bounds_max - model.bounds_min), kModelRadius, 1e-4 * kModelRadius);
  EXPECT_LT(floor.bounds_max.y, model.bounds_min.y) << "the floor stays below the model, never coplanar";
  EXPECT_NEAR(floor.bounds_max.x - floor.bounds_min.x, 4 * kModelRadius, 1e-4);
  std::vector<glm::vec3> corners;
  for (const Object* o : {&model, &floor})
    for (int i = 0; i < 8; ++i)
      corners.emplace_back(i & 1 ? o->bounds_max.x : o->bounds_min.x,
                           i & 2 ? o->bounds_max.y : o->bounds_min.y,
                           i & 4 ? o->bounds_max.z : o->bounds_min.z);
  for (int frame : {0, 30, 94, 188, 500}) {  // 94: the sway's peak (0.5 rad/s * 94/60 s = pi/2)
    const glm::vec3 light = s.light().path.at(frame);
    EXPECT_GT(glm::length(light - c), kModelRadius)
        << "frame " << frame << ": the light is outside the model";
    for (const glm::vec3& p : corners)
      EXPECT_LT(glm::length(p - light), s.light().far_plane)
          << "frame " << frame << ": far holds the whole scene";
  }
  EXPECT_NEAR(glm::length(s.light().path.amplitude), kModelRadius / 4, 1e-5);
  // Light and camera beyond the model's bounds on +x, +y and +z at every frame: every face of the bounds the
  // camera sees faces the light too (a box's three faces are lit, not only its top).
  for (int frame : {0, 94, 282}) {  // 282: the sway's other peak
    const glm::vec3 light = s.light().path.at(frame);
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_GT(light[axis], model.bounds_max[axis]) << "frame " << frame << ", axis " << axis;
      EXPECT_GT(s.camera.position[axis], model.bounds_max[axis]) << "axis " << axis;
    }
  }
  // The camera frames the bounding sphere: its angular radius is under half the vertical field of view.
  const float distance = glm::length(s.camera.position - c);
  EXPECT_LT(std::asin(kModelRadius / distance), glm::radians(s.camera.fov_y_degrees) / 2);
  EXPECT_NEAR(glm::length(s.camera.target - c), 0.0f, 1e-4f);
  for (const Vertex& v : s.vertices) ASSERT_NEAR(glm::length(v.normal), 1.0f, 1e-5f);
}

TEST(ModelPlacement, ScalesTheModelToTheRoomsSizeAndPlacesLightAndCameraOutsideIt) {
  // A box in millimetres, far from the origin: scaled (never moved), so the rebase remedy still has work to
  // do.
  const ModelPlacement p = place_model({1000, 0, 0}, {1400, 300, 0}, {}, "mm.obj");
  EXPECT_DOUBLE_EQ(p.scale, kModelRadius / 250.0);  // half of the 500 mm diagonal
  EXPECT_NEAR(p.center.x, 1200 * p.scale, 1e-9);
  // Half extents (4, 3, 0) in world units, then R (0.5, 0.75, 0.5) beyond them.
  EXPECT_NEAR(glm::length(p.light.base - p.center - glm::dvec3(4 + 2.5, 3 + 3.75, 0 + 2.5)), 0.0, 1e-9);
  EXPECT_NEAR(p.floor_y, -0.01 * kModelRadius, 1e-12);
  EXPECT_DOUBLE_EQ(p.light_near, 0.01 * kModelRadius);

  // Overrides are in the file's units and scale with the model; the far plane follows the light placed.
  LoadOptions o;
  o.light = LightPlacement{{1200, 5000, 0}, {0, 0, 0}};
  o.camera = CameraPlacement{{1200, 150, 2000}, std::nullopt};
  const ModelPlacement q = place_model({1000, 0, 0}, {1400, 300, 0}, o, "mm.obj");
  EXPECT_NEAR(q.light.base.y, 5000 * q.scale, 1e-9);
  EXPECT_EQ(q.light.amplitude, glm::vec3(0.0f));
  EXPECT_GT(q.light_far, (5000 - 0) * q.scale) << "far reaches the floor below a light placed high";
  EXPECT_NEAR(q.camera.position.z, 2000 * q.scale, 1e-9);
  EXPECT_EQ(*q.camera.target, q.center) << "no target given: the model's centre";

  EXPECT_THROW(place_model({1, 1, 1}, {1, 1, 1}, {}, "point.obj"), SceneError);
  EXPECT_THROW(place_model({0, 0, 0}, {INFINITY, 1, 1}, {}, "inf.obj"), SceneError);
}

TEST(ModelScene, AnOBJRunsByTheRuleWithAFloor) {
  // A tetrahedron in kilometres.
  const std::string path = write_file("tetra.obj",
                                      "v 0 0 0\nv 4000 0 0\nv 0 4000 0\nv 0 0 4000\n"
                                      "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  const Scene s = load_scene_file(path);
  EXPECT_EQ(s.name, "tetra");
  EXPECT_EQ(s.objects[0].kind, "obj");
  EXPECT_EQ(s.triangle_count(), 4u + 2u);
  expect_rule_holds(s);
  ASSERT_FALSE(s.notes.empty());
  EXPECT_NE(s.notes.back().find("placed by rule"), std::string::npos) << s.notes.back();
}

TEST(ModelScene, RebaseSubtractsThePlacedLightInDouble) {
  const std::string path = write_file("far.obj", "v 1e6 0 0\nv 1000001 0 0\nv 1e6 1 0\nf 1 2 3\n");
  LoadOptions rebased;
  rebased.rebase_origin = true;
  const Scene s = load_scene_file(path, rebased);
  EXPECT_EQ(s.light().path.base, glm::vec3(0.0f));
  EXPECT_NE(s.origin, glm::dvec3(0.0));
  EXPECT_LT(glm::length(s.camera.position), 4 * kModelRadius) << "stored relative to the light";
}

// A glTF model's KHR_lights_punctual point lights replace the rule's light: scaled with the model, range as
// far, the brightest at the tutorial's 0.3; `--light` moves the first of them and keeps the rest.
TEST(ModelScene, AGltfModelBringsItsOwnPointLights) {
  std::ifstream in(std::string(OMNISHADOW_TEST_SCENES_DIR) + "/../fuzz/seeds/gltf/triangle_embedded.gltf");
  nlohmann::json doc = nlohmann::json::parse(in);
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 10}, {"range", 3}},
                                                        {{"type", "point"}, {"color", {1, 0, 0}}}};
  doc["nodes"][0]["children"] = {1, 2};
  doc["nodes"].push_back(
      {{"translation", {0, 2, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  doc["nodes"].push_back(
      {{"translation", {1, 2, 1}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  const std::string path = write_file("lit.gltf", doc.dump());
  const Scene s = load_scene_file(path);
  ASSERT_EQ(s.point_lights.size(), 2u);
  const float scale = s.point_lights[0].far_plane / 3.0f;  // range 3 in the file's units
  EXPECT_NEAR(s.point_lights[0].path.base.y, 3.0f * scale, 1e-4f) << "(0, 1, 0) + (0, 2, 0), scaled";
  EXPECT_EQ(s.point_lights[0].path.amplitude, glm::vec3(0.0f)) << "a model's lights stand still";
  EXPECT_EQ(s.point_lights[0].color, glm::vec3(0.3f));
  EXPECT_NEAR(s.point_lights[1].color.r, 0.03f, 1e-6f) << "a tenth of the brightest";
  EXPECT_EQ(s.point_lights[1].color.g, 0.0f);
  for (const scene::Vertex& v : s.vertices)
    EXPECT_LT(glm::length(v.position - s.point_lights[1].path.base), s.point_lights[1].far_plane)
        << "no range: the far plane holds the whole scene";
  LoadOptions moved;
  moved.light = LightPlacement{{0, 5, 0}, {0, 0, 0}};
  const Scene m = load_scene_file(path, moved);
  ASSERT_EQ(m.point_lights.size(), 2u);
  EXPECT_NEAR(m.point_lights[0].path.base.y, 5.0f * scale, 1e-4f);
  EXPECT_EQ(m.point_lights[1], s.point_lights[1]);
}

TEST(ModelScene, LightAndCameraOverridesApplyToSceneFilesToo) {
  const std::string scenes = OMNISHADOW_TEST_SCENES_DIR;
  LoadOptions o;
  o.light = LightPlacement{{1, 2, -1}, {0, 0, 0.5f}};
  o.camera = CameraPlacement{{4, 4, 4}, glm::dvec3(0, -1, 0)};
  const Scene room = load_scene_file(scenes + "/room.json", o);
  EXPECT_EQ(room.light().path.base, glm::vec3(1, 2, -1));
  EXPECT_EQ(room.light().path.amplitude, glm::vec3(0, 0, 0.5f));
  EXPECT_EQ(room.light().far_plane, 25.0f) << "a scene file keeps its planes";
  EXPECT_EQ(room.camera.position, glm::vec3(4, 4, 4));
  EXPECT_EQ(room.camera.target, glm::vec3(0, -1, 0));
  o.rebase_origin = true;
  const Scene rebased = load_scene_file(scenes + "/room.json", o);
  EXPECT_EQ(rebased.origin, glm::dvec3(1, 2, -1)) << "the rebase follows the light placed by hand";
  EXPECT_EQ(rebased.light().path.base, glm::vec3(0.0f));

  LoadOptions up;
  up.camera = CameraPlacement{{0, 4, 0}, glm::dvec3(0, 0, 0)};
  EXPECT_THROW(load_scene_file(scenes + "/room.json", up), SceneError)
      << "looking along the scene's up vector";
  LoadOptions light_only;
  light_only.light = LightPlacement{};
  try {
    load_scene_file(scenes + "/spot.json", light_only);
    ADD_FAILURE() << "spot.json has no point light to move";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("--light"), std::string::npos) << e.what();
  }
  // A model seen from straight above: lookAt's up would be parallel, so the rule turns it.
  const std::string tetra =
      write_file("tetra2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n");
  LoadOptions above;
  above.camera = CameraPlacement{{0.25, 10, 0.25}, glm::dvec3(0.25, 0, 0.25)};
  const Scene s = load_scene_file(tetra, above);
  EXPECT_GT(glm::length(glm::cross(glm::normalize(s.camera.target - s.camera.position), s.camera.up)), 0.5f);
}

TEST(ModelScene, MissingAndDegenerateModelsAreOneLineNamingTheFile) {
  for (const std::string& path : {std::string("/nonexistent/model.glb"),
                                  write_file("point.obj", "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n"),
                                  write_file("truncated.glb", "glTF\x02")}) {
    try {
      load_scene_file(path);
      ADD_FAILURE() << path << " loaded";
    } catch (const SceneError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(std::filesystem::path(path).filename().string()), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

TEST(ModelScene, GlmarksBunnyByTheRule) {
  if (!std::filesystem::exists(kBunny))
    GTEST_SKIP() << kBunny << " missing: bash scripts/setup.sh installs glmark2-data";
  const Scene bunny = load_scene_file(kBunny);
  EXPECT_EQ(bunny.objects[0].vertex_count, 69666u * 3u) << "the Stanford bunny";
  expect_rule_holds(bunny);
}

TEST(ModelScene, AssimpsEngineByTheRule) {
  if (!std::filesystem::exists(kEngine))
    GTEST_SKIP() << kEngine << " missing: bash scripts/setup.sh installs assimp-testmodels";
  const Scene engine = load_scene_file(kEngine);
  EXPECT_EQ(engine.name, "2CylinderEngine");
  EXPECT_EQ(engine.objects[0].kind, "gltf");
  EXPECT_GT(engine.triangle_count(), 100000u);
  expect_rule_holds(engine);
}

TEST(ModelScene, TheDefaultMatrixsBunnyRoomHoldsTheBunnyClearOfWallsAndLight) {
  if (!std::filesystem::exists(kBunny))
    GTEST_SKIP() << kBunny << " missing: bash scripts/setup.sh installs glmark2-data";
  const Scene s = load_scene_file(std::string(OMNISHADOW_TEST_SCENES_DIR) + "/bunny.json");
  ASSERT_EQ(s.objects.size(), 2u);
  const Object& bunny = s.objects[1];
  EXPECT_EQ(bunny.vertex_count, 69666u * 3u);
  EXPECT_GT(bunny.bounds_min.y, -5.0f) << "above the floor, not coplanar with it";
  EXPECT_LT(bunny.bounds_min.y, -4.9f) << "standing on it";
  auto inside_room = [](const glm::vec3& p) {
    return std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}) < 5.0f;
  };
  EXPECT_TRUE(inside_room(bunny.bounds_min) && inside_room(bunny.bounds_max));
  for (int frame = 0; frame < 400; frame += 7) {
    const glm::vec3 l = s.light().path.at(frame);
    EXPECT_GT(l.y, bunny.bounds_max.y) << "frame " << frame << ": the light sways above the bunny";
    EXPECT_TRUE(inside_room(l)) << "frame " << frame;
  }
}

// Scene files place models like any shape: T * R * S and a grid of copies, each copy its own object.
TEST(ModelScene, SceneFilesRepeatModelsWithTransformsAndArrays) {
  const std::string tri = write_file("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  std::vector<std::string> files = {tri};
  if (std::filesystem::exists(kEngine))
    files.push_back(kEngine);  // else the OBJ alone: assimp-testmodels missing
  for (const std::string& file : files) {
    const std::string type = file.ends_with(".obj") ? "obj" : "gltf";
    const std::string text =
        R"({"light": {}, "objects": [{"name": "m", "type": ")" + type + R"(", "file": ")" + file +
        R"(", "translate": [10, 0, 0], "scale": 2, "rotate": {"degrees": 90, "axis": [0, 1, 0]},
                             "array": {"count": [3, 1, 2], "spacing": [5, 0, 7]}}]})";
    const Scene single = load_scene_text(
        R"({"light": {}, "objects": [{"type": ")" + type + R"(", "file": ")" + file + R"("}]})",
        "single.json");
    const Scene s = load_scene_text(text, "array.json");
    ASSERT_EQ(s.objects.size(), 6u) << file;
    EXPECT_EQ(s.objects[5].name, "m[2,0,1]");
    EXPECT_EQ(s.vertices.size(), 6 * single.vertices.size());
    // Copy [2,0,1]: vertex k is the model's vertex k rotated 90 degrees about +Y, doubled, moved by (20, 0,
    // 7).
    const Object& last = s.objects[5];
    for (uint32_t k = 0; k < last.vertex_count; k += 97) {
      const glm::vec3 p = single.vertices[k].position;
      const glm::vec3 expected = glm::vec3(20, 0, 7) + 2.0f * glm::vec3(p.z, p.y, -p.x);
      EXPECT_LT(glm::length(s.vertices[last.first_vertex + k].position - expected),
                1e-3f * (1 + glm::length(expected)))
          << file << " vertex " << k;
    }
  }
}

}  // namespace
}  // namespace omnishadow::scene
