#pragma once
// Wavefront OBJ meshes through tinyobjloader (Debian's libtinyobjloader-dev), for scene objects of type
// "obj".

#include <cstdint>
#include <string>
#include <vector>

#include "scenes/mesh_builders.h"  // MeshVertex

namespace omnishadow::scene {

// Every face of every group as counter-clockwise triangles in file order: n-gons triangulated by
// tinyobjloader (a quad split along its shorter diagonal, larger polygons fanned from their first corner). A
// corner's normal is the file's, normalised, where all three corners of the triangle name a non-zero one,
// else the triangle's face normal. Throws std::runtime_error with one line naming the file and what is wrong:
// unreadable, a line the library rejects (its message, with the line number), a vertex or normal index beyond
// the file's, a coordinate that is not finite, or no faces at all.
std::vector<MeshVertex> load_obj(const std::string& path);
// The same from the file's text; `name` stands for the file in errors (the fuzz target's entry).
std::vector<MeshVertex> load_obj_text(const std::string& text, const std::string& name);
// A larger file is refused before it is read (a billion-vertex claim needs a file of that size).
inline constexpr uintmax_t kMaxObjFileBytes = uintmax_t(1) << 30;

}  // namespace omnishadow::scene
