#pragma once
// glTF 2.0 models (.gltf with its buffers, or .glb) through tinygltf (Debian's libtinygltf-dev), for scene
// objects of type "gltf" and `--scene model.glb`.

#include <cstdint>
#include <string>
#include <vector>

#include "scenes/mesh_builders.h"  // MeshVertex

namespace omnishadow::scene {

// A KHR_lights_punctual point light at its node, in the model's units.
struct GltfPointLight {
  glm::dvec3 position{0.0};
  glm::vec3 color{1.0f};   // linear RGB, as the file gives it (default white)
  double intensity = 1.0;  // candela
  double range = 0.0;      // 0: infinite (the extension's default)
};

struct GltfModel {
  // Every triangle of the default scene (else scene 0, else every root node) in world space of the model:
  // node matrices and TRS composed down the hierarchy, counter-clockwise (a mirroring node's triangles are
  // re-wound), normals the file's (normalised) or the face's; each vertex coloured by its material's base
  // colour factor (glTF's default 1, 1, 1 without one; textures are not read).
  std::vector<MeshVertex> triangles;
  std::vector<glm::vec3> colors;  // per vertex, beside `triangles`
  // Primitives that are not triangles (points, lines, line loops and strips): skipped, counted and named.
  int skipped_primitives = 0;
  std::string skipped_modes;  // e.g. "LINES x2, POINTS x1"
  // KHR_lights_punctual: the point lights of the nodes visited, in visiting order (a shared node's light once
  // per instance); spot and directional lights are counted, not read.
  std::vector<GltfPointLight> point_lights;
  int skipped_lights = 0;
};

// Throws std::runtime_error with one line naming the file and what is wrong: unreadable or not glTF
// (tinygltf's first error line), a required compressed-geometry extension (Draco, meshopt, mesh
// quantization), a buffer URI that leaves the model's folder, an accessor or index beyond its buffer, a
// sparse accessor, a cyclic node graph, non-finite values, or more than `max_vertices` vertices (checked
// before they are read).
GltfModel load_gltf(const std::string& path, uint64_t max_vertices);
// The same from the file's bytes (glTF JSON, or GLB by its magic); external files are refused (the fuzz
// entry).
GltfModel load_gltf_bytes(const std::string& bytes, const std::string& name, uint64_t max_vertices);

}  // namespace omnishadow::scene
