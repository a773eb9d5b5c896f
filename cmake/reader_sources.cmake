# The code that reads untrusted files (scene files, results.json, images) and what it needs, with no graphics API,
# relative to the repository root, per floor: the main build's libraries hold each list beside the rest of their
# floor, and the libFuzzer targets (fuzz/CMakeLists.txt) build them all (OMNISHADOW_READER_SOURCES). One list
# per floor, so a reader added here is fuzzed. The model loaders link tinyobjloader and tinygltf (Debian's
# libtinyobjloader-dev, libtinygltf-dev).
set(OMNISHADOW_SCENE_READER_SOURCES
  scenes/scene_loader.cpp
  scenes/scene_lights.cpp
  scenes/mesh_builders.cpp
  scenes/obj_loader.cpp
  scenes/gltf_loader.cpp
  scenes/gltf_geometry.cpp
  scenes/model_scene.cpp)
set(OMNISHADOW_IO_SOURCES  # bench/io: the whole floor reads files
  bench/io/file_io.cpp
  bench/io/image_io.cpp
  bench/io/statistics.cpp
  bench/io/results_reader.cpp)
set(OMNISHADOW_TRUTH_READER_SOURCES bench/truth/image_compare.cpp)
set(OMNISHADOW_REPORT_READER_SOURCES bench/report/compare.cpp)
set(OMNISHADOW_READER_SOURCES
  ${OMNISHADOW_SCENE_READER_SOURCES}
  ${OMNISHADOW_IO_SOURCES}
  ${OMNISHADOW_TRUTH_READER_SOURCES}
  ${OMNISHADOW_REPORT_READER_SOURCES})
