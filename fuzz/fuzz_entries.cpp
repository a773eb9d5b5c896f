#include "fuzz/fuzz_entries.h"

#include <cmath>

#include "bench/report/compare.h"
#include "scenes/gltf_loader.h"
#include "scenes/obj_loader.h"
#include "scenes/scene.h"

namespace omnishadow::fuzz {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

std::string scene_invariants(const scene::Scene& s) {
  if (s.vertices.empty() || s.vertices.size() % 3 != 0) return "vertex count not a positive multiple of 3";
  for (const scene::Vertex& v : s.vertices) {
    if (!finite(v.position)) return "non-finite vertex position";
    if (!finite(v.normal) || std::fabs(glm::length(v.normal) - 1.0f) > 1e-3f)
      return "normal not finite and unit";
    if (!finite(v.color)) return "non-finite colour";
  }
  for (const scene::Object& o : s.objects)
    if (uint64_t(o.first_vertex) + o.vertex_count > s.vertices.size())
      return "object range outside the vertices";
  for (const scene::PointLight& l : s.point_lights) {
    if (!(l.near_plane > 0.0f) || !(l.far_plane > l.near_plane) || !std::isfinite(l.far_plane))
      return "light range not 0 < near < far < inf";
    if (!finite(l.path.at(0)) || !finite(l.path.at(12345))) return "light path not finite";
  }
  if (s.point_lights.empty() && s.map_lights.empty()) return "no light";
  if (s.point_lights.size() > size_t(scene::kMaxPointLights)) return "more point lights than the cap";
  const scene::Camera& c = s.camera;
  glm::vec3 view = c.target - c.position;
  if (!(glm::length(glm::cross(view, c.up)) > 0.0f)) return "camera basis degenerate";
  if (!(c.far_plane > c.near_plane) || c.width < 1 || c.height < 1) return "camera range or size invalid";
  return "";
}

std::string check_scene_input(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  scene::Scene s;
  try {
    // A source path in a folder that does not exist: relative OBJ paths in the input resolve to nothing.
    s = scene::load_scene_text(text, "/nonexistent-omnishadow-fuzz/fuzz.json");
  } catch (const scene::SceneError&) {
    return "";
  } catch (const std::exception& e) {
    return std::string("escaped exception: ") + e.what();
  }
  return scene_invariants(s);
}

std::string check_results_input(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  try {
    bench::RunData run = bench::parse_run(text, "fuzz.json", "/nonexistent-omnishadow-fuzz");
    bench::CompareOptions options;
    options.out_dir = "/nonexistent-omnishadow-fuzz/compare";
    bench::Comparison c = bench::compare_runs(run, run, options);
    bench::comparison_table(c, options);
    bench::comparison_markdown(c, options);
    bench::comparison_json(c, options).dump();
    for (const bench::CaseComparison& cc : c.cases) {
      if (!cc.work_changes.empty())
        return "a run compared with itself shows a work change: " + cc.work_changes[0];
      if (cc.verdict == "regression" || cc.verdict == "improvement")
        return "self-comparison gave " + cc.verdict;
    }
  } catch (const bench::CompareError&) {
    return "";
  } catch (const std::exception& e) {
    return std::string("escaped exception: ") + e.what();
  }
  return "";
}

std::string check_obj_input(const uint8_t* data, size_t size) {
  std::vector<scene::MeshVertex> mesh;
  try {
    mesh = scene::load_obj_text(std::string(reinterpret_cast<const char*>(data), size), "fuzz.obj");
  } catch (const std::runtime_error&) {
    return "";
  } catch (const std::exception& e) {
    return std::string("escaped exception: ") + e.what();
  }
  if (mesh.empty() || mesh.size() % 3 != 0) return "vertex count not a positive multiple of 3";
  for (const scene::MeshVertex& v : mesh) {
    if (!finite(v.position)) return "non-finite vertex position";
    if (!finite(v.normal) || std::fabs(glm::length(v.normal) - 1.0f) > 1e-3f)
      return "normal not finite and unit";
  }
  return "";
}

std::string check_gltf_input(const uint8_t* data, size_t size) {
  scene::GltfModel model;
  try {
    model =
        scene::load_gltf_bytes(std::string(reinterpret_cast<const char*>(data), size), "fuzz.glb", 1u << 20);
  } catch (const std::runtime_error&) {
    return "";
  } catch (const std::exception& e) {
    return std::string("escaped exception: ") + e.what();
  }
  if (model.triangles.empty() || model.triangles.size() % 3 != 0)
    return "vertex count not a positive multiple of 3";
  if (model.colors.size() != model.triangles.size()) return "not one colour per vertex";
  for (size_t i = 0; i < model.triangles.size(); ++i) {
    const scene::MeshVertex& v = model.triangles[i];
    if (!finite(v.position)) return "non-finite vertex position";
    if (!finite(v.normal) || std::fabs(glm::length(v.normal) - 1.0f) > 1e-3f)
      return "normal not finite and unit";
    const glm::vec3 c = model.colors[i];
    if (!finite(c) || glm::any(glm::lessThan(c, glm::vec3(0.0f))) ||
        glm::any(glm::greaterThan(c, glm::vec3(1.0f))))
      return "colour not finite in [0, 1]";
  }
  return "";
}

}  // namespace omnishadow::fuzz
