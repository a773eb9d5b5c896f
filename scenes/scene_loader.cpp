// Scene files: strict JSON with every field checked, so a typo is an error naming its JSON pointer rather
// than a silently different scene. The format is documented in scenes/README.md.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "scenes/gltf_loader.h"
#include "scenes/mesh_builders.h"
#include "scenes/model_scene.h"
#include "scenes/obj_loader.h"
#include "scenes/scene.h"
#include "scenes/scene_json.h"
#include "scenes/scene_lights.h"

namespace omnishadow::scene {

namespace {

using detail::Node;
using nlohmann::json;

bool finite(const glm::vec3& v) { return !glm::any(glm::isnan(v)) && !glm::any(glm::isinf(v)); }

// Unit vector of v for |v| anywhere in float's range: the squares in glm::length overflow above ~1e19.
// A zero or non-finite v gives NaN, which the caller rejects.
glm::vec3 normalize_wide(glm::vec3 v) {
  float m = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  if (!(m > 0.0f) || std::isinf(m)) return glm::vec3(NAN);
  v /= m;
  return v / glm::length(v);
}

Camera parse_camera(const Node& n, const glm::dvec3& origin) {
  n.expect_object({"position", "target", "up", "fov_y_degrees", "near", "far", "size", "path"});
  Camera c;
  c.position = glm::vec3(glm::dvec3(c.position) - origin);
  c.target = glm::vec3(glm::dvec3(c.target) - origin);
  if (n.has("position")) c.position = n.at("position").position(origin);
  if (n.has("target")) c.target = n.at("target").position(origin);
  if (n.has("up")) c.up = n.at("up").vec3();
  if (glm::length(c.target - c.position) == 0.0f) n.at("target").fail("target must differ from position");
  // lookAt builds its basis from cross(view, up): a zero or parallel up gives NaN in every matrix downstream.
  glm::vec3 side = glm::cross(glm::normalize(c.target - c.position), c.up);
  if (!(glm::length(side) > 1e-6f))
    (n.has("up") ? n.at("up") : n).fail("up must not be zero or parallel to the view");
  if (n.has("fov_y_degrees")) c.fov_y_degrees = static_cast<float>(n.at("fov_y_degrees").number_in(1, 179));
  if (n.has("near")) c.near_plane = static_cast<float>(n.at("near").number_in(1e-6, 1e30));
  if (n.has("far")) c.far_plane = static_cast<float>(n.at("far").number_in(1e-6, 1e30));
  if (c.far_plane <= c.near_plane) n.at("far").fail("far must be greater than near");
  if (n.has("size")) {
    Node s = n.at("size");
    if (!s.value().is_array() || s.value().size() != 2) s.fail("expected [width, height]");
    c.width = s.at(size_t{0}).integer_in(1, 16384);
    c.height = s.at(size_t{1}).integer_in(1, 16384);
  }
  if (n.has("path")) {
    c.path = detail::parse_path_fields(n.at("path"), LightPath{});
    if (!finite(c.path.amplitude) || !std::isfinite(c.path.frequency))
      n.at("path").fail("amplitude and frequency must be finite");
  }
  return c;
}

// A shape's triangles, and for a glTF model its materials' base colours per vertex (empty: the object's
// colour).
struct Shape {
  std::vector<MeshVertex> mesh;
  std::vector<glm::vec3> colors;
  std::string note;  // for Scene::notes
};

// A model file named by the object's "file", relative to the scene; the loader's error names the file.
std::string model_path(const Node& n, const std::string& scene_dir, const char* format) {
  std::filesystem::path file = n.at("file").string();
  if (file.is_relative()) file = std::filesystem::path(scene_dir) / file;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    n.at("file").fail(std::string("cannot open ") + format + " file " + file.string() +
                      " (missing or not a regular file" +
                      (file.string().starts_with("/usr/share/")
                           ? "; a Debian package's file: bash scripts/setup.sh installs it)"
                           : ")"));
  return file.string();
}

Shape build_shape(const Node& n, const std::string& type, const std::string& scene_dir) {
  if (type == "box") return {make_box(), {}};
  if (type == "plane") return {make_plane(), {}};
  if (type == "sphere") {
    int lon = 32, lat = 16;
    if (n.has("segments")) {
      Node s = n.at("segments");
      if (!s.value().is_array() || s.value().size() != 2) s.fail("expected [longitude, latitude]");
      // 1024 x 1024 segments = 6.3 M vertices, under the scene's vertex cap below.
      lon = s.at(size_t{0}).integer_in(3, 1024);
      lat = s.at(size_t{1}).integer_in(2, 1024);
    }
    return {make_sphere(lon, lat), {}};
  }
  if (type == "obj" || type == "gltf") {
    const std::string file = model_path(n, scene_dir, type == "obj" ? "OBJ" : "glTF");
    try {
      if (type == "obj") return {load_obj(file), {}};
      GltfModel model = load_gltf(file, kMaxSceneVertices);
      std::string note;
      if (model.skipped_primitives > 0)
        note = n.pointer() + " (" + file + "): skipped " + model.skipped_modes +
               " (not triangles; shadows need surfaces)";
      return {std::move(model.triangles), std::move(model.colors), note};
    } catch (const std::exception& e) {
      n.at("file").fail(e.what());
    }
  }
  n.at("type").fail("unknown object type '" + type + "' (valid: box, plane, sphere, obj, gltf)");
}

// An object's placement as its node gives it: translation (relative to the scene's origin), rotation, scale,
// colour, and the optional grid of copies (count [x,y,z], spacing [x,y,z]) that keeps a geometry-heavy scene
// a short file.
struct ObjectPlacement {
  glm::vec3 translate{0.0f}, scale{1.0f}, color{0.8f};
  glm::mat4 rotation{1.0f};
  glm::ivec3 count{1};
  glm::vec3 spacing{0.0f};
};

ObjectPlacement read_placement(const Node& n, const glm::dvec3& origin) {
  ObjectPlacement p;
  p.translate = glm::vec3(-origin);
  if (n.has("translate")) p.translate = n.at("translate").position(origin);
  if (n.has("scale")) p.scale = n.at("scale").scale();
  if (n.has("color")) {
    p.color = n.at("color").vec3();
    if (glm::any(glm::lessThan(p.color, glm::vec3(0.0f))))
      n.at("color").fail("colour components must be >= 0");
  }
  if (n.has("rotate")) {
    Node r = n.at("rotate");
    r.expect_object({"degrees", "axis"});
    glm::vec3 axis = r.at("axis").vec3();
    if (glm::length(axis) == 0.0f) r.at("axis").fail("axis must not be zero");
    p.rotation = glm::rotate(glm::mat4(1.0f), glm::radians(static_cast<float>(r.at("degrees").number())),
                             glm::normalize(axis));
  }
  if (n.has("array")) {
    Node a = n.at("array");
    a.expect_object({"count", "spacing"});
    Node c = a.at("count");
    if (!c.value().is_array() || c.value().size() != 3) c.fail("expected [nx, ny, nz]");
    for (int k = 0; k < 3; ++k) p.count[k] = c.at(static_cast<size_t>(k)).integer_in(1, 1000);
    p.spacing = a.at("spacing").vec3();
  }
  return p;
}

void add_object(Scene& scene, const Node& n, const std::string& scene_dir, size_t index) {
  n.expect_object({"name", "type", "translate", "rotate", "scale", "color", "inside", "segments", "file",
                   "array", "path"});
  std::string type = n.at("type").string();
  const Shape shape = build_shape(n, type, scene_dir);
  if (!shape.note.empty()) scene.notes.push_back(shape.note);
  const std::vector<MeshVertex>& mesh = shape.mesh;
  const ObjectPlacement placement = read_placement(n, scene.origin);
  const glm::vec3 &translate = placement.translate, &scale = placement.scale, &color = placement.color,
                  &spacing = placement.spacing;
  const glm::mat4& rotation = placement.rotation;
  const glm::ivec3& count = placement.count;
  bool inside = n.has("inside") && n.at("inside").boolean();
  // A moving caster: every instance of an array moves together, by the same offset.
  const LightPath motion = n.has("path") ? detail::parse_path_fields(n.at("path"), LightPath{}) : LightPath{};
  if (!finite(motion.amplitude) || !std::isfinite(motion.frequency))
    n.at("path").fail("amplitude and frequency must be finite");
  if (static_cast<uint64_t>(count.x) * count.y * count.z * mesh.size() + scene.vertices.size() >
      kMaxSceneVertices)
    n.fail("object too large: more than " + std::to_string(kMaxSceneVertices) + " vertices in the scene");

  std::string base_name = n.has("name") ? n.at("name").string() : type + "#" + std::to_string(index);
  for (int ix = 0; ix < count.x; ++ix)
    for (int iy = 0; iy < count.y; ++iy)
      for (int iz = 0; iz < count.z; ++iz) {
        glm::vec3 offset = spacing * glm::vec3(ix, iy, iz);
        // Seed order: model = T * R * S.
        glm::mat4 model = glm::translate(glm::mat4(1.0f), translate + offset) * rotation *
                          glm::scale(glm::mat4(1.0f), scale);
        // Normals of T * R * S transform by R * S^-1. Dividing by the scale directly (not inverting the 3x3)
        // keeps them finite for scales down to ~1e-30, where the matrix determinant underflows to 0.
        glm::mat3 normal_rotation(rotation);
        Object obj;
        obj.name = count == glm::ivec3(1) ? base_name
                                          : base_name + "[" + std::to_string(ix) + "," + std::to_string(iy) +
                                                "," + std::to_string(iz) + "]";
        obj.kind = type;
        obj.first_vertex = static_cast<uint32_t>(scene.vertices.size());
        obj.vertex_count = static_cast<uint32_t>(mesh.size());
        obj.cull_back_faces = !inside && (type == "box" || type == "sphere");
        obj.bounds_min = glm::vec3(INFINITY);
        obj.bounds_max = glm::vec3(-INFINITY);
        for (size_t i = 0; i < mesh.size(); ++i) {
          const MeshVertex& mv = mesh[i];
          Vertex v;
          v.position = glm::vec3(model * glm::vec4(mv.position, 1.0f));
          v.normal = normalize_wide(normal_rotation * (mv.normal / scale));
          if (inside) v.normal = -v.normal;  // seen from inside: the tutorial's reverseNormals
          v.color = shape.colors.empty() || n.has("color") ? color
                                                           : shape.colors[i];  // "color" overrides a model's
          // Defensive: inputs are bounded by 1e30, but a subnormal scale makes normal / scale overflow. Such
          // geometry would put NaN/Inf into every buffer.
          if (!finite(v.position) || !finite(v.normal))
            n.fail("transform gives non-finite vertex positions or normals (scale/translate too extreme)");
          obj.bounds_min = glm::min(obj.bounds_min, v.position);
          obj.bounds_max = glm::max(obj.bounds_max, v.position);
          scene.vertices.push_back(v);
        }
        obj.motion = motion;
        obj.rest_bounds_min = obj.bounds_min;
        obj.rest_bounds_max = obj.bounds_max;
        scene.objects.push_back(obj);
      }
}

// --light / --camera on a scene file: the first point light's path and the camera replaced, the file's planes
// kept.
void apply_placement(Scene& scene, const LoadOptions& options, const std::string& source) {
  if (options.light) {
    if (!scene.has_point_light())
      throw SceneError(source +
                       ": --light moves the point light, and this scene has none (only spot/directional)");
    LightPath& path = scene.point_lights.front().path;  // the first point light's: the others keep theirs
    path.base = glm::vec3(options.light->base - scene.origin);
    path.amplitude = options.light->amplitude;
    path.frequency = kSeedLightFrequency;  // irrelevant for a light standing still
    path.phase = 0.0f;
  }
  if (options.camera) {
    Camera& c = scene.camera;
    c.position = glm::vec3(options.camera->position - scene.origin);
    if (options.camera->target) c.target = glm::vec3(*options.camera->target - scene.origin);
    c.path = LightPath{};  // the placed camera stands still, or sways as --camera says
    c.path.amplitude = options.camera->amplitude;
    c.path.frequency = kSeedLightFrequency;
    if (!(glm::length(c.target - c.position) > 0.0f))
      throw SceneError(source + ": --camera position coincides with the camera's target");
    if (!(glm::length(glm::cross(glm::normalize(c.target - c.position), c.up)) > 1e-6f))
      throw SceneError(source +
                       ": --camera looks along the scene's up vector; give another position or target");
  }
}

}  // namespace

// The position the rebase remedy subtracts: the point light's, else the first spot light's, else 0. Read from
// the raw JSON (in double) before anything is parsed; malformed values are reported by the normal parse.
glm::dvec3 rebase_origin_of(const json& doc) {
  auto position_of = [](const json& light) -> glm::dvec3 {
    if (!light.is_object() || !light.contains("position")) return glm::dvec3(0.0);
    const json& p = light["position"];
    if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() || !p[2].is_number())
      return glm::dvec3(0.0);
    glm::dvec3 v(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) ? v : glm::dvec3(0.0);
  };
  if (doc.contains("light")) return position_of(doc["light"]);
  if (doc.contains("lights") && doc["lights"].is_array()) {
    for (const json& l : doc["lights"])
      if (l.is_object() && l.value("type", "point") == "point") return position_of(l);
    for (const json& l : doc["lights"])
      if (l.is_object() && l.contains("type") && l["type"] == "spot") return position_of(l);
  }
  return glm::dvec3(0.0);
}

Scene load_scene_text(const std::string& text, const std::string& source, const LoadOptions& options) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    throw SceneError(source + ": malformed JSON at byte " + std::to_string(e.byte) + ": " +
                     std::string(e.what()).substr(std::string(e.what()).rfind(':') + 2));
  } catch (const json::exception& e) {  // out_of_range 406: a number beyond double ("1e400")
    throw SceneError(
        source + ": malformed JSON: " + std::string(e.what()).substr(std::string(e.what()).find(']') + 2));
  }
  Node root(doc, "", source);
  root.expect_object({"format", "description", "camera", "light", "lights", "objects"});
  if (root.has("format") && root.at("format").string() != "omnishadow-scene/1")
    root.at("format").fail("unsupported format (expected \"omnishadow-scene/1\")");

  Scene scene;
  if (options.rebase_origin && doc.is_object())
    scene.origin = options.light ? options.light->base : rebase_origin_of(doc);
  scene.source = source;
  scene.name = std::filesystem::path(source).stem().string();
  scene.camera = parse_camera(
      root.has("camera") ? root.at("camera") : Node(json::object(), "/camera", source), scene.origin);
  parse_lights(root, scene);

  Node objects = root.at("objects");
  if (!objects.value().is_array()) objects.fail("expected an array of objects");
  if (objects.value().empty()) objects.fail("a scene needs at least one object");
  std::string scene_dir = std::filesystem::path(source).parent_path().string();
  for (size_t i = 0; i < objects.value().size(); ++i) add_object(scene, objects.at(i), scene_dir, i);
  apply_placement(scene, options, source);
  return scene;
}

bool is_model_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".obj" || ext == ".gltf" || ext == ".glb";
}

Scene load_scene_file(const std::string& path, const LoadOptions& options) {
  if (is_model_file(path)) return load_model_scene(path, options);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open scene file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return load_scene_text(buffer.str(), path, options);
}

}  // namespace omnishadow::scene
