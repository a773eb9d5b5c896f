// glTF 2.0 models through tinygltf (scenes/gltf_loader.h): third-party models from Debian's assimp-testmodels
// load with the triangles they hold, the same model as .glb, .gltf + .bin and embedded agrees, and every
// malformed file is one line naming the file and what is wrong - never a crash or a read beyond a buffer.

#include "scenes/gltf_loader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "bench/io/file_io.h"

namespace omnishadow::scene {
namespace {

namespace fs = std::filesystem;
const fs::path kModels =
    "/usr/share/assimp/models/glTF2";  // assimp-testmodels (scripts/setup.sh installs it)
constexpr uint64_t kLimit = 1u << 24;

#define REQUIRE_TESTMODELS()      \
  if (!fs::is_directory(kModels)) \
  GTEST_SKIP() << kModels << " missing: install Debian's assimp-testmodels (bash scripts/setup.sh does)"

std::string seeds(const char* name) {
  return (fs::path(OMNISHADOW_SOURCE_DIR) / "fuzz/seeds/gltf" / name).string();
}

TEST(GltfLoader, ThirdPartyModelsLoadAndAgreeAcrossContainers) {
  REQUIRE_TESTMODELS();
  const GltfModel glb = load_gltf((kModels / "BoxTextured-glTF-Binary/BoxTextured.glb").string(), kLimit);
  EXPECT_EQ(glb.triangles.size(), 36u) << "a box: 12 triangles";
  for (const char* other :
       {"BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Embedded/BoxTextured.gltf"}) {
    const GltfModel m = load_gltf((kModels / other).string(), kLimit);
    ASSERT_EQ(m.triangles.size(), glb.triangles.size()) << other;
    for (size_t i = 0; i < m.triangles.size(); ++i)
      EXPECT_EQ(m.triangles[i].position, glb.triangles[i].position) << other;
  }
  const GltfModel engine =
      load_gltf((kModels / "2CylinderEngine-glTF-Binary/2CylinderEngine.glb").string(), kLimit);
  EXPECT_GT(engine.triangles.size(), 100000u) << "the engine's many meshes through its node hierarchy";
  EXPECT_EQ(engine.colors.size(), engine.triangles.size());
}

TEST(GltfLoader, SeedsCoverMaterialsHierarchyStripsAndMirroring) {
  const GltfModel tri = load_gltf(seeds("triangle_embedded.gltf"), kLimit);
  ASSERT_EQ(tri.triangles.size(), 3u);
  EXPECT_EQ(tri.triangles[1].position, glm::vec3(1, 1, 0)) << "the node's translation";
  EXPECT_EQ(tri.colors[0], glm::vec3(0.8f, 0.2f, 0.1f)) << "the material's base colour factor";
  const GltfModel strip = load_gltf(seeds("strip_hierarchy.glb"), kLimit);
  ASSERT_EQ(strip.triangles.size(), 6u) << "a 4-vertex strip: two triangles";
  for (size_t t = 0; t < 6;
       t += 3) {  // mirrored by the parent's z scale of -1, re-wound: still counter-clockwise
    const glm::vec3 a = strip.triangles[t].position, b = strip.triangles[t + 1].position,
                    c = strip.triangles[t + 2].position;
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), strip.triangles[t].normal), 0.0f) << "triangle " << t / 3;
  }
}

TEST(GltfLoader, NonTrianglePrimitivesAreSkippedAndCounted) {
  REQUIRE_TESTMODELS();
  int skipped = 0, loaded = 0;
  for (int i = 0; i <= 9; ++i) {
    char name[96];
    std::snprintf(name, sizeof name, "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_%02d.gltf",
                  i);
    try {
      const GltfModel m = load_gltf((kModels / name).string(), kLimit);
      ++loaded;
      EXPECT_EQ(m.triangles.size() % 3, 0u);
    } catch (const std::runtime_error& e) {
      ++skipped;
      EXPECT_NE(std::string(e.what()).find("no triangles (skipped: "), std::string::npos) << e.what();
    }
  }
  EXPECT_GT(loaded, 0);
  EXPECT_GT(skipped, 0) << "points and lines are reported, not drawn";
}

struct BadGltf {
  const char* label;
  std::function<std::string(const fs::path& dir)> make;  // writes the file, returns its path
  const char* expected;                                  // a substring of the one-line error
};

std::string write(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

// Five vertices drawn by one primitive of each kind: POINTS once, LINES twice (skipped, counted by mode), a
// TRIANGLE_STRIP and a TRIANGLE_FAN over all five (unrolled by the spec's rules, each triangle
// counter-clockwise as its strip or fan orders it). A fan read as a strip, a strip without its every-other
// reversal, a skip count stuck at 0 or the modes named alike each fail here.
TEST(GltfLoader, StripsAndFansUnrollAndOtherModesAreCountedByName) {
  const fs::path dir = fs::temp_directory_path() / ("omnishadow_gltf_modes_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::vector<glm::vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 2, 0}};
  std::string bin(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(glm::vec3));
  const std::vector<glm::vec3> normals(v.size(), glm::vec3(0, 0, 1));
  bin.append(reinterpret_cast<const char*>(normals.data()), normals.size() * sizeof(glm::vec3));
  write(dir / "modes.bin", bin);
  using J = nlohmann::json;
  J primitives = J::array();
  for (int mode : {0 /* POINTS */, 1 /* LINES */, 1, 5 /* TRIANGLE_STRIP */, 6 /* TRIANGLE_FAN */})
    primitives.push_back({{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"mode", mode}});
  const J doc = {{"asset", {{"version", "2.0"}}},
                 {"scene", 0},
                 {"scenes", J::array({{{"nodes", J::array({0})}}})},
                 {"nodes", J::array({{{"mesh", 0}}})},
                 {"meshes", J::array({{{"primitives", primitives}}})},
                 {"buffers", J::array({{{"uri", "modes.bin"}, {"byteLength", bin.size()}}})},
                 {"bufferViews", J::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 60}},
                                           {{"buffer", 0}, {"byteOffset", 60}, {"byteLength", 60}}})},
                 {"accessors",
                  J::array({{{"bufferView", 0},
                             {"componentType", 5126},
                             {"count", 5},
                             {"type", "VEC3"},
                             {"min", {0, 0, 0}},
                             {"max", {1, 2, 0}}},
                            {{"bufferView", 1}, {"componentType", 5126}, {"count", 5}, {"type", "VEC3"}}})}};
  const GltfModel m = load_gltf(write(dir / "modes.gltf", doc.dump()), kLimit);
  fs::remove_all(dir);
  EXPECT_EQ(m.skipped_primitives, 3);
  EXPECT_EQ(m.skipped_modes, "LINES x2, POINTS x1");
  // Strip: (0 1 2), then (2 1 3) reversed to keep the winding, then (2 3 4). Fan: (0 1 2), (0 2 3), (0 3 4).
  const std::vector<int> want = {0, 1, 2, 2, 1, 3, 2, 3, 4, 0, 1, 2, 0, 2, 3, 0, 3, 4};
  ASSERT_EQ(m.triangles.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i)
    EXPECT_EQ(m.triangles[i].position, v[size_t(want[i])]) << "corner " << i << " of triangle " << i / 3;
}

// The triangle seed with one edit of its JSON.
std::string edited_seed(const fs::path& path, const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json doc = nlohmann::json::parse(bench::read_file(seeds("triangle_embedded.gltf")));
  edit(doc);
  return write(path, doc.dump());
}

std::vector<BadGltf> bad_files() {
  using J = nlohmann::json;
  return {
      {"truncated glb",
       [](const fs::path& d) {
         return write(d / "truncated.glb", bench::read_file(seeds("strip_hierarchy.glb")).substr(0, 100));
       },
       "truncated.glb: "},
      {"not gltf", [](const fs::path& d) { return write(d / "text.gltf", "hello"); }, "text.gltf: "},
      {"uri leaves the folder",
       [](const fs::path& d) {
         return edited_seed(d / "escape.gltf", [](J& j) { j["buffers"][0]["uri"] = "../outside.bin"; });
       },
       "leaves the model's folder"},
      // A buffer missing from the model's own folder is missing, not an escape.
      {"buffer missing",
       [](const fs::path& d) {
         return edited_seed(d / "missing.gltf", [](J& j) { j["buffers"][0]["uri"] = "missing.bin"; });
       },
       "missing.bin is missing (a buffer the model names; looked for in "},
      // Random bytes named .glb: no GLB header, said as such (not a JSON parser's exception).
      {"random glb", [](const fs::path& d) { return write(d / "random.glb", "\x93\x11garbage\x01"); },
       "random.glb: not a binary glTF (a .glb starts with 'glTF')"},
      {"count beyond the buffer",
       [](const fs::path& d) {
         return edited_seed(d / "count.gltf", [](J& j) { j["accessors"][0]["count"] = 4; });
       },
       "run beyond the buffer view"},
      {"billion vertices",
       [](const fs::path& d) {
         return edited_seed(d / "billion.gltf", [](J& j) { j["accessors"][2]["count"] = 1000000000; });
       },
       "indices"},
      {"cyclic nodes",
       [](const fs::path& d) {
         return edited_seed(d / "cycle.gltf", [](J& j) {
           j["nodes"][0]["children"] = J::array({1});
           j["nodes"].push_back(J{{"children", J::array({0})}});
         });
       },
       "cyclic node graph"},
      {"accessor that does not exist",
       [](const fs::path& d) {
         return edited_seed(d / "index.gltf", [](J& j) { j["meshes"][0]["primitives"][0]["indices"] = 7; });
       },
       "accessor"},
      {"draco required",
       [](const fs::path& d) {
         return edited_seed(d / "draco.gltf", [](J& j) {
           j["extensionsRequired"] = J::array({"KHR_draco_mesh_compression"});
           j["extensionsUsed"] = J::array({"KHR_draco_mesh_compression"});
         });
       },
       "KHR_draco_mesh_compression"},
      {"sparse accessor",
       [](const fs::path& d) {
         return edited_seed(d / "sparse.gltf", [](J& j) {
           j["accessors"][0]["sparse"] = J{{"count", 1},
                                           {"indices", {{"bufferView", 2}, {"componentType", 5123}}},
                                           {"values", {{"bufferView", 1}}}};
         });
       },
       "sparse"},
  };
}

// KHR_lights_punctual: a point light sits at its node's origin under the node's transforms; spot and
// directional lights are counted; a node naming a light the file lacks is one line.
TEST(GltfLoader, PunctualPointLightsStandWhereTheirNodesPutThem) {
  std::ifstream in(seeds("triangle_embedded.gltf"));
  nlohmann::json doc = nlohmann::json::parse(in);
  using J = nlohmann::json;
  auto light_node = [](int light, J transform) {
    transform["extensions"] = J{{"KHR_lights_punctual", {{"light", light}}}};
    return transform;
  };
  doc["extensionsUsed"] = {"KHR_lights_punctual"};
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 20}, {"range", 7}},
      {{"type", "spot"}, {"spot", J::object()}},
      {{"type", "point"}}};
  doc["nodes"][0]["children"] = {1, 2, 3};  // node 0 moves its children by (0, 1, 0)
  doc["nodes"].push_back(light_node(0, {{"translation", {2, 0, 0}}}));
  doc["nodes"].push_back(light_node(1, J::object()));
  doc["nodes"].push_back(light_node(2, {{"translation", {0, 0, -1}}}));
  const GltfModel m = load_gltf_bytes(doc.dump(), "lights.gltf", kLimit);
  ASSERT_EQ(m.point_lights.size(), 2u);
  EXPECT_EQ(m.point_lights[0].position, glm::dvec3(2, 1, 0));
  EXPECT_EQ(m.point_lights[0].color, glm::vec3(1.0f, 0.5f, 0.25f));
  EXPECT_EQ(m.point_lights[0].intensity, 20.0);
  EXPECT_EQ(m.point_lights[0].range, 7.0);
  EXPECT_EQ(m.point_lights[1].position, glm::dvec3(0, 1, -1));
  EXPECT_EQ(m.point_lights[1].range, 0.0) << "no range: infinite";
  EXPECT_EQ(m.skipped_lights, 1) << "the spot light";
  doc["nodes"][2]["extensions"]["KHR_lights_punctual"]["light"] = 9;
  try {
    load_gltf_bytes(doc.dump(), "lights.gltf", kLimit);
    ADD_FAILURE() << "a node naming light 9 of 3 was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "lights.gltf: node 2: KHR_lights_punctual light 9 does not exist");
  }
}

// Textures are never decoded, so one that is missing or lies outside the model's folder blocks nothing: the
// geometry loads (the sandbox still reads nothing outside the folder).
TEST(GltfLoader, TexturesThatCannotBeReadDoNotBlockTheGeometry) {
  const fs::path dir = fs::temp_directory_path() / "omnishadow_gltf_loader_test" / "textures";
  fs::create_directories(dir);
  const std::string path = edited_seed(dir / "textured.gltf", [](nlohmann::json& j) {
    j["images"] = {{{"uri", "missing.png"}}, {{"uri", "../elsewhere/albedo.png"}}};
    j["textures"] = {{{"source", 0}}, {{"source", 1}}};
    j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 1}};
    j["materials"][0]["normalTexture"] = {{"index", 0}};
  });
  const GltfModel m = load_gltf(path, kLimit);
  EXPECT_EQ(m.triangles.size(), 3u);
  EXPECT_EQ(m.colors[0], glm::vec3(0.8f, 0.2f, 0.1f)) << "the base colour factor, as without textures";
}

TEST(GltfLoader, MalformedFilesAreOneLineNamingTheFile) {
  const fs::path dir = fs::temp_directory_path() / "omnishadow_gltf_loader_test" / "models";
  fs::create_directories(dir);
  write(dir.parent_path() / "outside.bin", std::string(100, '\0'));
  for (const BadGltf& bad : bad_files()) {
    const std::string path = bad.make(dir);
    try {
      load_gltf(path, kLimit);
      ADD_FAILURE() << bad.label << ": accepted";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << bad.label << ": " << what;
      EXPECT_EQ(what.rfind(path, 0), 0u) << bad.label << ": " << what;
      EXPECT_NE(what.find(bad.expected), std::string::npos) << bad.label << ": " << what;
    }
  }
}

// assimp's own broken models: each refused in one line (its test suite's reasons: indices out of range, a
// node that is its own descendant, a schema failure, Draco-compressed geometry, a missing buffer file).
TEST(GltfLoader, AssimpsBrokenModelsAreRefusedInOneLine) {
  REQUIRE_TESTMODELS();
  for (const char* name :
       {"IndexOutOfRange/IndexOutOfRange.gltf", "IndexOutOfRange/AllIndicesOutOfRange.gltf",
        "RecursiveNodes/RecursiveNodes.gltf", "SchemaFailures/sceneWrongType.gltf",
        "draco/2CylinderEngine.gltf", "MissingBin/BoxTextured.gltf"}) {
    try {
      load_gltf((kModels / name).string(), kLimit);
      ADD_FAILURE() << name << ": accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << name << ": " << e.what();
    }
  }
}

}  // namespace
}  // namespace omnishadow::scene
