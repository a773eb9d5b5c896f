#pragma once
// What each fuzz target does with one input, shared by the libFuzzer binaries (clang, fuzz/CMakeLists.txt)
// and by the regression test that replays tests/fuzz_regressions/ in the normal g++ build.
//
// Contract under test: an input is either rejected with the loader's own one-line error type, or accepted
// into a value whose invariants hold. Anything else (another exception, a sanitizer report, a broken
// invariant) is a finding. The functions return "" when the contract held, otherwise a description of the
// violation.

#include <cstddef>
#include <cstdint>
#include <string>

#include "scenes/scene.h"

namespace omnishadow::fuzz {

// What an accepted scene must satisfy; "" when it does.
std::string scene_invariants(const scene::Scene& s);

// The scene loader: SceneError, or a scene with finite unit normals, finite positions, consistent object
// ranges, a valid light range and a camera whose view basis exists.
std::string check_scene_input(const uint8_t* data, size_t size);

// The results reader used by compare/merge: CompareError, or a run that compare_runs, the table, the markdown
// and the JSON summary all handle without throwing (compared with itself: no timing, work or image change).
std::string check_results_input(const uint8_t* data, size_t size);

// The OBJ loader (tinyobjloader): std::runtime_error, or whole triangles with finite positions and unit
// normals.
std::string check_obj_input(const uint8_t* data, size_t size);

// The glTF loader (tinygltf, glTF JSON or GLB; no external files): std::runtime_error, or whole triangles
// with finite positions, unit normals and one finite colour in [0, 1] per vertex.
std::string check_gltf_input(const uint8_t* data, size_t size);

}  // namespace omnishadow::fuzz
