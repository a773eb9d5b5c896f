// Replays every input the fuzzers ever flagged (tests/fuzz_regressions/<target>/) and their seeds through the
// same contract the libFuzzer targets check (fuzz/fuzz_entries.h), in the normal build: a fixed finding stays
// fixed.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>

#include "bench/io/file_io.h"
#include "fuzz/fuzz_entries.h"

namespace fs = std::filesystem;
using Check = std::function<std::string(const uint8_t*, size_t)>;

namespace {

int replay(const std::vector<fs::path>& folders, const Check& check) {
  int inputs = 0;
  for (const fs::path& folder : folders) {
    if (!fs::is_directory(folder)) continue;
    for (const auto& entry : fs::directory_iterator(folder)) {
      if (!entry.is_regular_file() || entry.path().extension() == ".md") continue;
      std::string bytes = omnishadow::bench::read_file(entry.path().string());
      std::string violation = check(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
      EXPECT_EQ(violation, "") << entry.path();
      ++inputs;
    }
  }
  return inputs;
}

const fs::path kRoot = OMNISHADOW_SOURCE_DIR;

}  // namespace

TEST(FuzzRegressions, SceneLoaderInputsKeepTheContract) {
  int n = replay({kRoot / "tests/fuzz_regressions/scene", kRoot / "fuzz/seeds/scene", kRoot / "scenes"},
                 omnishadow::fuzz::check_scene_input);
  EXPECT_GE(n, 5) << "regression inputs and seeds went missing";
}

TEST(FuzzRegressions, ResultsReaderInputsKeepTheContract) {
  int n = replay({kRoot / "tests/fuzz_regressions/results", kRoot / "fuzz/seeds/results"},
                 omnishadow::fuzz::check_results_input);
  EXPECT_GE(n, 2) << "regression inputs and seeds went missing";
}

TEST(FuzzRegressions, ObjLoaderInputsKeepTheContract) {
  int n = replay({kRoot / "tests/fuzz_regressions/obj", kRoot / "fuzz/seeds/obj"},
                 omnishadow::fuzz::check_obj_input);
  EXPECT_GE(n, 3) << "regression inputs and seeds went missing";
}

TEST(FuzzRegressions, GltfLoaderInputsKeepTheContract) {
  int n = replay({kRoot / "tests/fuzz_regressions/gltf", kRoot / "fuzz/seeds/gltf"},
                 omnishadow::fuzz::check_gltf_input);
  EXPECT_GE(n, 2) << "regression inputs and seeds went missing";
}

// The contract itself must be able to fail, or the replay proves nothing.
TEST(FuzzRegressions, InvariantsCatchABrokenScene) {
  std::string text = R"({"light": {}, "objects": [{"type": "box"}]})";
  omnishadow::scene::Scene s = omnishadow::scene::load_scene_text(text, "inline.json");
  EXPECT_EQ(omnishadow::fuzz::scene_invariants(s), "");
  s.vertices[4].normal = glm::vec3(NAN);
  EXPECT_NE(omnishadow::fuzz::scene_invariants(s), "");
}

// Found while writing the contract: a scale of 1e-30 underflowed the inverted normal matrix and baked NaN
// normals.
TEST(FuzzRegressions, ExtremeTransformsBakeFiniteUnitNormals) {
  for (const char* object :
       {R"({"type": "box", "scale": 1e-30})", R"({"type": "sphere", "scale": [1e-30, 1e30, 1]})",
        R"({"type": "box", "scale": 1e30, "translate": [1e30, 0, 0],
                                 "array": {"count": [3, 1, 1], "spacing": [1e30, 0, 0]}})"}) {
    std::string text = std::string(R"({"light": {}, "objects": [)") + object + "]}";
    omnishadow::scene::Scene s = omnishadow::scene::load_scene_text(text, "inline.json");
    EXPECT_EQ(omnishadow::fuzz::scene_invariants(s), "") << object;
  }
  std::string subnormal = R"({"light": {}, "objects": [{"type": "box", "scale": 1e-40}]})";
  try {
    omnishadow::scene::load_scene_text(subnormal, "inline.json");
    ADD_FAILURE() << "a subnormal scale was accepted";
  } catch (const omnishadow::scene::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("inline.json: /objects/0"), std::string::npos) << e.what();
  }
}
