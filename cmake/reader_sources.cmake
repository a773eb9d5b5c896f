# The code that reads untrusted files (scene files, results.json, images) and what it needs, with no graphics API,
# relative to the repository root: the libFuzzer targets (fuzz/CMakeLists.txt) build exactly these, and the main
# build's omnishadow_core holds them beside the rest. One list, so a reader added here is fuzzed. Both link
# tinyobjloader and tinygltf (Debian's libtinyobjloader-dev, libtinygltf-dev) for the model loaders.
set(OMNISHADOW_READER_SOURCES
  scenes/scene_loader.cpp
  scenes/mesh_builders.cpp
  scenes/obj_loader.cpp
  scenes/gltf_loader.cpp
  scenes/gltf_geometry.cpp
  scenes/model_scene.cpp
  bench/results/file_io.cpp
  bench/results/image_io.cpp
  bench/truth/image_compare.cpp
  bench/results/statistics.cpp
  bench/results/results_reader.cpp
  bench/results/compare.cpp)
