#include "scenes/obj_loader.h"

#include <tiny_obj_loader.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "scenes/model_util.h"

namespace omnishadow::scene {
namespace {

glm::vec3 triple(const std::vector<tinyobj::real_t>& values, int index) {
  const size_t i = size_t(index) * 3;
  return {values[i], values[i + 1], values[i + 2]};
}

}  // namespace

std::vector<MeshVertex> load_obj(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error("cannot open OBJ file " + path);
  const uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec || bytes > kMaxObjFileBytes)
    throw std::runtime_error(path + ": " +
                             (ec ? "cannot read its size" : "larger than 1 GiB (kMaxObjFileBytes)"));
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<size_t>(bytes), '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(text.size())))
    throw std::runtime_error("cannot read OBJ file " + path);
  return load_obj_text(text, path);
}

std::vector<MeshVertex> load_obj_text(const std::string& text, const std::string& path) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.triangulation_method = "simple";
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // Materials are not read (no .mtl text): a mesh's colour comes from the scene file.
  if (!reader.ParseFromString(text, "", config))
    throw std::runtime_error(path + ": " + first_line(reader.Error(), "unreadable"));
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  for (tinyobj::real_t v : attrib.vertices)
    if (!std::isfinite(v)) throw std::runtime_error(path + ": a vertex coordinate is not finite");
  for (tinyobj::real_t v : attrib.normals)
    if (!std::isfinite(v)) throw std::runtime_error(path + ": a normal coordinate is not finite");
  // The library only warns about an index beyond the file's vertices; it must not reach the arrays.
  const int positions = int(attrib.vertices.size() / 3), normals = int(attrib.normals.size() / 3);
  std::vector<MeshVertex> out;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    size_t offset = 0;
    for (unsigned corners : shape.mesh.num_face_vertices) {
      if (corners != 3)
        throw std::runtime_error(path + ": a face of " + std::to_string(corners) +
                                 " corners was not triangulated");
      MeshVertex tri[3];
      bool all_normals = true;
      for (unsigned k = 0; k < 3; ++k) {
        const tinyobj::index_t idx = shape.mesh.indices[offset + k];
        if (idx.vertex_index < 0 || idx.vertex_index >= positions)
          throw std::runtime_error(path + ": a face names vertex " + std::to_string(idx.vertex_index + 1) +
                                   " of " + std::to_string(positions));
        if (idx.normal_index >= normals)
          throw std::runtime_error(path + ": a face names normal " + std::to_string(idx.normal_index + 1) +
                                   " of " + std::to_string(normals));
        tri[k].position = triple(attrib.vertices, idx.vertex_index);
        // Files need not store unit normals; a zero one counts as none.
        const glm::vec3 n =
            idx.normal_index >= 0 ? triple(attrib.normals, idx.normal_index) : glm::vec3(0.0f);
        const float length = glm::length(n);
        if (length > 0.0f && std::isfinite(length))
          tri[k].normal = n / length;
        else
          all_normals = false;
      }
      offset += 3;
      if (!all_normals) {
        const glm::vec3 n = face_normal(tri[0].position, tri[1].position, tri[2].position);
        for (MeshVertex& v : tri) v.normal = n;
      }
      out.insert(out.end(), tri, tri + 3);
    }
  }
  if (out.empty()) throw std::runtime_error(path + ": no faces");
  return out;
}

}  // namespace omnishadow::scene
