// OBJ meshes through tinyobjloader (scenes/obj_loader.h): polygons triangulated, negative indices, the file's
// normals or face normals; and one line naming the file for each malformed file, never a read beyond the
// arrays.

#include "scenes/obj_loader.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "scenes/scene.h"

namespace omnishadow::scene {
namespace {

std::string write_obj(const std::string& name, const std::string& text) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "omnishadow_obj_loader_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

TEST(ObjLoader, TriangulatesPolygonsAndResolvesNegativeIndices) {
  // A unit quad (two triangles) and a pentagon (three), the pentagon by negative (relative) indices.
  const std::string path = write_obj("polygons.obj",
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
                                     "v 0 0 1\nv 1 0 1\nv 1.5 0.5 1\nv 1 1 1\nv 0 1 1\nf -5 -4 -3 -2 -1\n");
  const std::vector<MeshVertex> v = load_obj(path);
  ASSERT_EQ(v.size(), (2u + 3u) * 3u);
  for (size_t i = 0; i < v.size(); ++i) {
    EXPECT_NEAR(v[i].normal.z, 1.0f, 1e-6f) << "counter-clockwise from +z: the face normal, vertex " << i;
    EXPECT_EQ(v[i].position.z, i < 6 ? 0.0f : 1.0f);
  }
}

TEST(ObjLoader, KeepsTheFilesNormalsNormalisedWhereEveryCornerHasOne) {
  const std::string path = write_obj("normals.obj",
                                     "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 3 0 4\nvn 0 0 0\n"
                                     "f 1//1 2//1 3//1\nf 1//1 2//2 3//1\n");
  const std::vector<MeshVertex> v = load_obj(path);
  ASSERT_EQ(v.size(), 6u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(glm::length(v[i].normal - glm::vec3(0.6f, 0.0f, 0.8f)), 0.0f, 1e-6f);
    EXPECT_EQ(v[3 + i].normal, glm::vec3(0.0f, 0.0f, 1.0f))
        << "a zero normal counts as none: the face normal";
  }
}

struct BadObj {
  const char* name;
  const char* text;
  const char* expected;  // a substring of the one-line error
};

class ObjLoaderErrors : public ::testing::TestWithParam<BadObj> {};

TEST_P(ObjLoaderErrors, OneLineNamingTheFile) {
  const BadObj& bad = GetParam();
  const std::string path = write_obj(bad.name, bad.text);
  try {
    load_obj(path);
    FAIL() << "accepted: " << bad.text;
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << "error must be one line: " << what;
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(bad.expected), std::string::npos) << "expected '" << bad.expected << "' in: " << what;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Malformed, ObjLoaderErrors,
    ::testing::Values(BadObj{"beyond.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "names vertex 9 of 3"},
                      BadObj{"negative_beyond.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -7\n", "of 3"},
                      BadObj{"normal_beyond.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//4\n",
                             "names normal 4 of 1"},
                      BadObj{"zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line"},
                      BadObj{"infinite.obj", "v 1e999 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "not finite"},
                      BadObj{"no_faces.obj", "v 0 0 0\nv 1 0 0\n", "no faces"},
                      BadObj{"empty.obj", "", "no faces"},
                      BadObj{"binary.obj",
                             "\x7f"
                             "ELF\x02\x01\x01\0\0\0",
                             "no faces"}),
    [](const ::testing::TestParamInfo<BadObj>& info) { return "case" + std::to_string(info.index); });

// The error is one line that names the path it could not read.
TEST(ObjLoader, AFolderOrMissingFileIsNamed) {
  for (const std::string& path :
       {std::string("/nonexistent/model.obj"), std::filesystem::temp_directory_path().string()}) {
    try {
      load_obj(path);
      ADD_FAILURE() << path << " loaded";
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
    }
  }
}

}  // namespace
}  // namespace omnishadow::scene
