#include "scenes/gltf_geometry.h"

#include <cmath>
#include <cstring>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <map>
#include <stdexcept>

#include "scenes/model_util.h"

namespace omnishadow::scene {
namespace {

// Geometry the loader cannot decode: a model that requires one is refused by name rather than drawn empty.
constexpr const char* kCompressedGeometry[] = {"KHR_draco_mesh_compression", "EXT_meshopt_compression",
                                               "KHR_mesh_quantization"};
// Node instances visited (a node may be shared): bounds a small file that fans out exponentially.
constexpr uint64_t kMaxNodeInstances = 1'000'000;
// Deeper hierarchies are refused before the recursion could exhaust the stack.
constexpr int kMaxNodeDepth = 256;

struct Context {
  const tinygltf::Model& model;
  const std::string& name;
  uint64_t max_vertices;
  GltfModel out;
  uint64_t node_instances = 0;
  std::map<std::string, int> skipped;  // primitive mode name -> count

  [[noreturn]] void fail(const std::string& why) const { throw std::runtime_error(name + ": " + why); }
};

bool finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

glm::dmat4 local_matrix(const Context& cx, const tinygltf::Node& node, int index) {
  const std::string where = "node " + std::to_string(index);
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) cx.fail(where + ": matrix must have 16 numbers");
    const glm::dmat4 m = glm::make_mat4(node.matrix.data());  // column-major, as glTF stores it
    if (!finite(m)) cx.fail(where + ": matrix is not finite");
    return m;
  }
  glm::dmat4 t(1.0), r(1.0), s(1.0);
  if (!node.translation.empty()) {
    if (node.translation.size() != 3) cx.fail(where + ": translation must have 3 numbers");
    t = glm::translate(glm::dmat4(1.0), glm::make_vec3(node.translation.data()));
  }
  if (!node.rotation.empty()) {
    if (node.rotation.size() != 4) cx.fail(where + ": rotation must have 4 numbers");
    const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1],
                       node.rotation[2]);  // glTF: x, y, z, w
    const double length = glm::length(q);
    if (!(length > 0.0) || !std::isfinite(length))
      cx.fail(where + ": rotation is not a finite non-zero quaternion");
    r = glm::mat4_cast(q / length);
  }
  if (!node.scale.empty()) {
    if (node.scale.size() != 3) cx.fail(where + ": scale must have 3 numbers");
    s = glm::scale(glm::dmat4(1.0), glm::make_vec3(node.scale.data()));
  }
  const glm::dmat4 m = t * r * s;
  if (!finite(m)) cx.fail(where + ": translation, rotation or scale is not finite");
  return m;
}

// The bytes of accessor `index` after every bound is checked: element k starts at data + k * stride.
struct View {
  const unsigned char* data = nullptr;
  size_t count = 0, stride = 0;
};

View accessor_view(const Context& cx, int index, int type, std::initializer_list<int> component_types,
                   const std::string& what) {
  const tinygltf::Model& m = cx.model;
  if (index < 0 || size_t(index) >= m.accessors.size())
    cx.fail(what + ": accessor " + std::to_string(index) + " does not exist");
  const tinygltf::Accessor& a = m.accessors[size_t(index)];
  const std::string where = what + " (accessor " + std::to_string(index) + ")";
  if (a.sparse.isSparse) cx.fail(where + ": sparse accessors are not supported");
  if (a.type != type) cx.fail(where + ": wrong element type");
  bool known = false;
  for (int c : component_types) known |= a.componentType == c;
  if (!known) cx.fail(where + ": unsupported component type " + std::to_string(a.componentType));
  const int component_bytes = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
  const int components = tinygltf::GetNumComponentsInType(uint32_t(a.type));
  if (component_bytes <= 0 || components <= 0) cx.fail(where + ": unknown component or element type");
  const size_t element = size_t(component_bytes) * size_t(components);
  if (a.count == 0) return {};
  if (a.bufferView < 0 || size_t(a.bufferView) >= m.bufferViews.size()) cx.fail(where + ": no buffer view");
  const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
  if (v.buffer < 0 || size_t(v.buffer) >= m.buffers.size()) cx.fail(where + ": buffer view names no buffer");
  const size_t buffer_bytes = m.buffers[size_t(v.buffer)].data.size();
  if (v.byteOffset > buffer_bytes || v.byteLength > buffer_bytes - v.byteOffset)
    cx.fail(where + ": buffer view beyond its buffer (" + std::to_string(buffer_bytes) + " bytes)");
  const size_t stride = v.byteStride ? v.byteStride : element;
  if (stride < element) cx.fail(where + ": byte stride smaller than an element");
  // The last element must end inside the view; written so that no product can overflow.
  if (a.byteOffset > v.byteLength || element > v.byteLength - a.byteOffset ||
      (a.count - 1) > (v.byteLength - a.byteOffset - element) / stride)
    cx.fail(where + ": " + std::to_string(a.count) + " elements run beyond the buffer view (" +
            std::to_string(v.byteLength) + " bytes)");
  return {m.buffers[size_t(v.buffer)].data.data() + v.byteOffset + a.byteOffset, a.count, stride};
}

glm::vec3 read_vec3(const View& v, size_t k) {
  glm::vec3 out;
  std::memcpy(&out, v.data + k * v.stride, sizeof out);  // unaligned-safe
  return out;
}

uint32_t read_index(const View& v, size_t k, int component_type) {
  const unsigned char* p = v.data + k * v.stride;
  if (component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return *p;
  if (component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
    uint16_t i;
    std::memcpy(&i, p, sizeof i);
    return i;
  }
  uint32_t i;
  std::memcpy(&i, p, sizeof i);
  return i;
}

const char* mode_name(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS:
      return "POINTS";
    case TINYGLTF_MODE_LINE:
      return "LINES";
    case TINYGLTF_MODE_LINE_LOOP:
      return "LINE_LOOP";
    case TINYGLTF_MODE_LINE_STRIP:
      return "LINE_STRIP";
    default:
      return "unknown mode";
  }
}

// The primitive's corner list as triangles (strips and fans unrolled), indices into its positions.
std::vector<uint32_t> triangle_corners(const Context& cx, const tinygltf::Primitive& p, size_t positions,
                                       const std::string& where) {
  std::vector<uint32_t> corners;
  if (p.indices >= 0) {
    const int type = cx.model.accessors.size() > size_t(p.indices)
                         ? cx.model.accessors[size_t(p.indices)].componentType
                         : 0;
    const View v =
        accessor_view(cx, p.indices, TINYGLTF_TYPE_SCALAR,
                      {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                      where + " indices");
    if (v.count > cx.max_vertices)
      cx.fail(where + ": more than " + std::to_string(cx.max_vertices) + " indices");
    corners.reserve(v.count);
    for (size_t k = 0; k < v.count; ++k) {
      const uint32_t i = read_index(v, k, type);
      if (i >= positions)
        cx.fail(where + ": index " + std::to_string(i) + " beyond its " + std::to_string(positions) +
                " vertices");
      corners.push_back(i);
    }
  } else {
    corners.resize(positions);
    for (size_t k = 0; k < positions; ++k) corners[k] = uint32_t(k);
  }
  const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
  std::vector<uint32_t> out;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    corners.resize(corners.size() - corners.size() % 3);
    return corners;
  }
  for (size_t k = 2; k < corners.size(); ++k) {
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)  // every other triangle reversed to keep the winding
      out.insert(out.end(),
                 k % 2 ? std::initializer_list<uint32_t>{corners[k - 1], corners[k - 2], corners[k]}
                       : std::initializer_list<uint32_t>{corners[k - 2], corners[k - 1], corners[k]});
    else  // TRIANGLE_FAN
      out.insert(out.end(), {corners[0], corners[k - 1], corners[k]});
  }
  return out;
}

glm::vec3 base_color(const Context& cx, int material) {
  if (material < 0 || size_t(material) >= cx.model.materials.size()) return glm::vec3(1.0f);
  const std::vector<double>& f = cx.model.materials[size_t(material)].pbrMetallicRoughness.baseColorFactor;
  if (f.size() < 3 || !std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2]))
    return glm::vec3(1.0f);
  return glm::clamp(glm::vec3(float(f[0]), float(f[1]), float(f[2])), 0.0f, 1.0f);
}

void add_primitive(Context& cx, const tinygltf::Primitive& p, const glm::dmat4& world,
                   const std::string& where) {
  const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
      mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    ++cx.skipped[mode_name(mode)];
    return;
  }
  for (const char* ext : kCompressedGeometry)
    if (p.extensions.count(ext))
      cx.fail(where + " uses " + std::string(ext) + " (compressed geometry is not decoded)");
  const auto position = p.attributes.find("POSITION");
  if (position == p.attributes.end()) cx.fail(where + ": no POSITION attribute");
  const View positions = accessor_view(cx, position->second, TINYGLTF_TYPE_VEC3,
                                       {TINYGLTF_COMPONENT_TYPE_FLOAT}, where + " POSITION");
  View normals;
  if (const auto normal = p.attributes.find("NORMAL"); normal != p.attributes.end()) {
    normals = accessor_view(cx, normal->second, TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT},
                            where + " NORMAL");
    if (normals.count != positions.count) cx.fail(where + ": NORMAL and POSITION counts differ");
  }
  const std::vector<uint32_t> corners = triangle_corners(cx, p, positions.count, where);
  if (corners.size() + cx.out.triangles.size() > cx.max_vertices)
    cx.fail("more than " + std::to_string(cx.max_vertices) + " vertices");
  const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(world)));
  const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;  // re-wind to stay counter-clockwise
  const glm::vec3 color = base_color(cx, p.material);
  for (size_t t = 0; t + 2 < corners.size(); t += 3) {
    const uint32_t tri[3] = {corners[t], corners[t + (mirrored ? 2 : 1)], corners[t + (mirrored ? 1 : 2)]};
    glm::dvec3 world_position[3];
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 local = read_vec3(positions, tri[k]);
      world_position[k] = glm::dvec3(world * glm::dvec4(glm::dvec3(local), 1.0));
      const glm::vec3 stored(world_position[k]);
      if (!std::isfinite(stored.x) || !std::isfinite(stored.y) || !std::isfinite(stored.z))
        cx.fail(where + ": a vertex position is not finite (in the file or after its node transforms)");
    }
    const glm::vec3 face = face_normal(world_position[0], world_position[1], world_position[2]);
    for (int k = 0; k < 3; ++k) {
      glm::vec3 n = face;
      if (normals.data) {
        const glm::dvec3 file_normal = normal_matrix * glm::dvec3(read_vec3(normals, tri[k]));
        const double length = glm::length(file_normal);
        if (length > 0.0 && std::isfinite(length)) n = glm::vec3(file_normal / length);
      }
      cx.out.triangles.push_back({glm::vec3(world_position[k]), n});
      cx.out.colors.push_back(color);
    }
  }
}

// The node's KHR_lights_punctual light, if any: a point light at the node's origin (the extension puts every
// light there, pointing down -Z), range and colour as the file gives them.
void add_light(Context& cx, const tinygltf::Node& node, int index, const glm::dmat4& world) {
  const auto ext = node.extensions.find("KHR_lights_punctual");
  if (ext == node.extensions.end() || !ext->second.Has("light")) return;
  const tinygltf::Value& which = ext->second.Get("light");
  const int light = which.IsInt() ? which.Get<int>() : -1;
  if (light < 0 || size_t(light) >= cx.model.lights.size())
    cx.fail("node " + std::to_string(index) + ": KHR_lights_punctual light " + std::to_string(light) +
            " does not exist");
  const tinygltf::Light& l = cx.model.lights[size_t(light)];
  if (l.type != "point") {
    ++cx.out.skipped_lights;
    return;
  }
  GltfPointLight p;
  p.position = glm::dvec3(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
  if (l.color.size() == 3) p.color = glm::vec3(l.color[0], l.color[1], l.color[2]);
  p.intensity = l.intensity;
  p.range = l.range;
  if (!std::isfinite(p.position.x) || !std::isfinite(p.position.y) || !std::isfinite(p.position.z) ||
      !std::isfinite(p.intensity) || p.intensity < 0.0 || !std::isfinite(p.range) || p.range < 0.0 ||
      glm::any(glm::lessThan(p.color, glm::vec3(0.0f))) || !std::isfinite(p.color.x + p.color.y + p.color.z))
    cx.fail("KHR_lights_punctual light " + std::to_string(light) +
            ": position, colour, intensity and range must be finite and not negative");
  cx.out.point_lights.push_back(p);
}

void add_node(Context& cx, int index, const glm::dmat4& parent, std::vector<bool>& on_path, int depth) {
  const tinygltf::Model& m = cx.model;
  if (depth > kMaxNodeDepth) cx.fail("the node hierarchy is deeper than " + std::to_string(kMaxNodeDepth));
  if (index < 0 || size_t(index) >= m.nodes.size())
    cx.fail("node " + std::to_string(index) + " does not exist");
  if (on_path[size_t(index)])
    cx.fail("node " + std::to_string(index) + " is its own ancestor (a cyclic node graph)");
  if (++cx.node_instances > kMaxNodeInstances)
    cx.fail("the node graph expands to more than " + std::to_string(kMaxNodeInstances) + " node instances");
  const tinygltf::Node& node = m.nodes[size_t(index)];
  const glm::dmat4 world = parent * local_matrix(cx, node, index);
  add_light(cx, node, index, world);
  if (node.mesh >= 0) {
    if (size_t(node.mesh) >= m.meshes.size())
      cx.fail("node " + std::to_string(index) + ": mesh " + std::to_string(node.mesh) + " does not exist");
    const tinygltf::Mesh& mesh = m.meshes[size_t(node.mesh)];
    for (size_t p = 0; p < mesh.primitives.size(); ++p)
      add_primitive(cx, mesh.primitives[p], world,
                    "mesh " + std::to_string(node.mesh) + " primitive " + std::to_string(p));
  }
  on_path[size_t(index)] = true;
  for (int child : node.children) add_node(cx, child, world, on_path, depth + 1);
  on_path[size_t(index)] = false;
}

std::vector<int> root_nodes(const Context& cx) {
  const tinygltf::Model& m = cx.model;
  if (!m.scenes.empty()) {
    const int s = m.defaultScene >= 0 && size_t(m.defaultScene) < m.scenes.size() ? m.defaultScene : 0;
    return m.scenes[size_t(s)].nodes;
  }
  std::vector<bool> is_child(m.nodes.size(), false);
  for (const tinygltf::Node& n : m.nodes)
    for (int c : n.children)
      if (c >= 0 && size_t(c) < m.nodes.size()) is_child[size_t(c)] = true;
  std::vector<int> roots;
  for (size_t i = 0; i < m.nodes.size(); ++i)
    if (!is_child[i]) roots.push_back(int(i));
  return roots;
}

}  // namespace

GltfModel gltf_model_from(const tinygltf::Model& model, const std::string& name, uint64_t max_vertices) {
  Context cx{model, name, max_vertices, {}, 0, {}};
  for (const std::string& ext : model.extensionsRequired)
    for (const char* compressed : kCompressedGeometry)
      if (ext == compressed) cx.fail("requires " + ext + " (compressed geometry is not decoded)");
  std::vector<bool> on_path(model.nodes.size(), false);
  for (int root : root_nodes(cx)) add_node(cx, root, glm::dmat4(1.0), on_path, 0);
  for (const auto& [mode, count] : cx.skipped) {
    cx.out.skipped_primitives += count;
    cx.out.skipped_modes += (cx.out.skipped_modes.empty() ? "" : ", ") + mode + " x" + std::to_string(count);
  }
  if (cx.out.triangles.empty())
    cx.fail("no triangles" +
            (cx.out.skipped_modes.empty() ? std::string() : " (skipped: " + cx.out.skipped_modes + ")"));
  return cx.out;
}

}  // namespace omnishadow::scene
