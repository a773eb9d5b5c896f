// A model run as a scene: the placement rule (model_scene.h) and the baking of the model and its floor.

#include "scenes/model_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "scenes/gltf_loader.h"
#include "scenes/mesh_builders.h"
#include "scenes/obj_loader.h"

namespace omnishadow::scene {

namespace {

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Farthest distance from either end of `light`'s path to any of `points`.
double farthest_from_path(const LightPlacement& light, const std::vector<glm::dvec3>& points) {
  double d = 0.0;
  for (double side : {-1.0, 1.0}) {
    const glm::dvec3 at = light.base + side * glm::dvec3(light.amplitude);
    for (const glm::dvec3& p : points) d = std::max(d, glm::length(p - at));
  }
  return d;
}

}  // namespace

ModelPlacement place_model(const glm::dvec3& lo, const glm::dvec3& hi, const LoadOptions& overrides,
                           const std::string& source) {
  if (!finite(lo) || !finite(hi) || glm::any(glm::greaterThan(lo, hi)))
    throw SceneError(source + ": the model has no finite bounds to place a light and camera from");
  ModelPlacement p;
  const double file_radius = 0.5 * glm::length(hi - lo);
  if (!(file_radius > 0.0) || !std::isfinite(file_radius))
    throw SceneError(source + ": the model is a single point (its bounds have no extent)");
  p.scale = kModelRadius / file_radius;
  p.center = p.scale * 0.5 * (lo + hi);
  p.radius = kModelRadius;
  const double r = p.radius;
  const glm::dvec3& c = p.center;
  const glm::dvec3 world_lo = p.scale * lo, world_hi = p.scale * hi;
  p.floor_y = world_lo.y - 0.01 * r;
  p.floor_half_size = 2.0 * r;

  if (overrides.light) {
    p.light.base = p.scale * overrides.light->base;
    p.light.amplitude = glm::vec3(p.scale * glm::dvec3(overrides.light->amplitude));
  } else {
    // Beyond the bounds on +x, +y and +z, the camera's side: every face of the bounds the camera sees is
    // lit, and the sway (x +- R/4) never brings the light back over them.
    const glm::dvec3 half = 0.5 * (world_hi - world_lo);
    p.light.base = c + half + r * glm::dvec3(0.5, 0.75, 0.5);
    p.light.amplitude = glm::vec3(static_cast<float>(0.25 * r), 0.0f, 0.0f);
  }
  std::vector<glm::dvec3> corners;
  for (int i = 0; i < 8; ++i)
    corners.emplace_back(i & 1 ? world_hi.x : world_lo.x, i & 2 ? world_hi.y : world_lo.y,
                         i & 4 ? world_hi.z : world_lo.z);
  for (int i = 0; i < 4; ++i)
    corners.emplace_back(c.x + (i & 1 ? 1 : -1) * p.floor_half_size, p.floor_y,
                         c.z + (i & 2 ? 1 : -1) * p.floor_half_size);
  p.light_near = 0.01 * r;
  p.light_far = 1.01 * farthest_from_path(p.light, corners);
  if (!(p.light_far > p.light_near))  // a light placed by hand far beyond float's range
    throw SceneError(source + ": --light leaves no depth range between near " + std::to_string(p.light_near) +
                     " and far " + std::to_string(p.light_far));

  if (overrides.camera) {
    p.camera.position = p.scale * overrides.camera->position;
    p.camera.target = overrides.camera->target ? p.scale * *overrides.camera->target : c;
    p.camera.amplitude = glm::vec3(p.scale * glm::dvec3(overrides.camera->amplitude));
  } else {
    p.camera.position = c + 3.0 * r * glm::normalize(glm::dvec3(0.55, 0.45, 1.0));
    p.camera.target = c;
  }
  p.camera_near = 0.01 * r;
  // A swaying camera strays up to |amplitude| from where it is put, and the model with it.
  p.camera_far = glm::length(p.camera.position - *p.camera.target) + 3.0 * r +
                 glm::length(glm::dvec3(p.camera.amplitude));
  return p;
}

namespace {

// The model's triangles and (glTF) per-vertex colours, in the file's units; loader errors become SceneError.
struct ModelMesh {
  std::string kind;  // obj, gltf
  std::vector<MeshVertex> mesh;
  std::vector<glm::vec3> colors;       // empty: the default grey
  std::vector<GltfPointLight> lights;  // glTF's KHR_lights_punctual point lights, in the file's units
  std::vector<std::string> notes;      // skipped primitives and lights, for Scene::notes
};

ModelMesh read_model(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw SceneError(path + ": cannot open model (missing or not a regular file)");
  ModelMesh m;
  m.kind = ext == ".obj" ? "obj" : "gltf";
  try {
    if (m.kind == "obj") {
      m.mesh = load_obj(path);
    } else {
      GltfModel model = load_gltf(path, kMaxSceneVertices);
      m.mesh = std::move(model.triangles);
      m.colors = std::move(model.colors);
      m.lights = std::move(model.point_lights);
      if (model.skipped_primitives > 0)
        m.notes.push_back(path + ": skipped " + model.skipped_modes +
                          " (not triangles; shadows need surfaces)");
      if (model.skipped_lights > 0)
        m.notes.push_back(path + ": skipped " + std::to_string(model.skipped_lights) +
                          " KHR_lights_punctual spot/directional light(s) (point lights only)");
    }
  } catch (const SceneError&) {
    throw;
  } catch (const std::exception& e) {
    throw SceneError(e.what());
  }
  if (m.mesh.size() + 6 > kMaxSceneVertices)
    throw SceneError(path + ": model too large: more than " + std::to_string(kMaxSceneVertices) +
                     " vertices");
  return m;
}

// Appends `vertices` as one object: world_of(file position) in double, stored relative to the scene's origin.
template <typename WorldOf, typename ColorOf>
void add_baked_object(Scene& scene, std::string name, std::string kind,
                      const std::vector<MeshVertex>& vertices, WorldOf world_of, ColorOf color_of) {
  Object obj;
  obj.name = std::move(name);
  obj.kind = std::move(kind);
  obj.first_vertex = static_cast<uint32_t>(scene.vertices.size());
  obj.vertex_count = static_cast<uint32_t>(vertices.size());
  obj.bounds_min = glm::vec3(INFINITY);
  obj.bounds_max = glm::vec3(-INFINITY);
  for (size_t i = 0; i < vertices.size(); ++i) {
    Vertex v{glm::vec3(world_of(vertices[i].position) - scene.origin), vertices[i].normal, color_of(i)};
    obj.bounds_min = glm::min(obj.bounds_min, v.position);
    obj.bounds_max = glm::max(obj.bounds_max, v.position);
    scene.vertices.push_back(v);
  }
  scene.objects.push_back(obj);
}

// The model's own point lights (glTF KHR_lights_punctual), scaled with the model and standing still: range
// as far (infinite: 1% beyond a bound on the farthest point of the model and floor), the rule's near, colours
// relative to the brightest light's 0.3 (the tutorial's white light; candela mean nothing to its unitless
// lighting).
std::vector<PointLight> model_lights(const std::vector<GltfPointLight>& lights, const ModelPlacement& place,
                                     const glm::dvec3& origin, const std::string& path) {
  double brightest = 0.0;
  for (const GltfPointLight& l : lights)
    brightest = std::max(brightest, l.intensity * std::max({l.color.r, l.color.g, l.color.b}));
  std::vector<PointLight> out;
  for (size_t i = 0; i < lights.size() && out.size() < size_t(kMaxPointLights); ++i) {
    PointLight p;
    p.near_plane = static_cast<float>(place.light_near);
    const glm::dvec3 at = place.scale * lights[i].position;
    p.path.base = glm::vec3(at - origin);
    // Everything lies within the floor's corners' distance from the centre (the floor is 4R wide).
    const double reach = std::sqrt(2.0 * place.floor_half_size * place.floor_half_size +
                                   (place.center.y - place.floor_y) * (place.center.y - place.floor_y));
    p.far_plane = static_cast<float>(lights[i].range > 0.0 ? place.scale * lights[i].range
                                                           : 1.01 * (glm::length(at - place.center) + reach));
    if (!(p.far_plane > 2.0f * p.near_plane) || !std::isfinite(p.far_plane))
      throw SceneError(path + ": KHR_lights_punctual point light " + std::to_string(i) + ": range " +
                       std::to_string(lights[i].range) + " leaves no depth range beyond near " +
                       std::to_string(place.light_near / place.scale) + " (file units)");
    p.color = brightest > 0.0 ? glm::vec3(0.3 * lights[i].intensity / brightest) * lights[i].color
                              : glm::vec3(0.0f);
    out.push_back(p);
  }
  return out;
}

// The placed light (or the model's own lights) and camera, stored relative to the scene's origin; the note
// that says how they were placed.
void set_light_and_camera(Scene& scene, const ModelPlacement& place, const LoadOptions& options,
                          const std::vector<GltfPointLight>& file_lights, const std::string& path) {
  auto stored = [&](const glm::dvec3& world) { return glm::vec3(world - scene.origin); };
  scene.point_lights = model_lights(file_lights, place, scene.origin, path);
  if (scene.point_lights.empty() || options.light) {  // the rule's light, or --light's: the first
    if (scene.point_lights.empty()) scene.point_lights.emplace_back();
    PointLight& light = scene.point_lights.front();
    light.path.base = stored(place.light.base);
    light.path.amplitude = place.light.amplitude;
    light.path.frequency = kSeedLightFrequency;
    light.near_plane = static_cast<float>(place.light_near);
    light.far_plane = static_cast<float>(place.light_far);
    light.color = PointLight{}.color;
  }
  scene.camera.position = stored(place.camera.position);
  scene.camera.target = stored(*place.camera.target);
  scene.camera.near_plane = static_cast<float>(place.camera_near);
  scene.camera.far_plane = static_cast<float>(place.camera_far);
  scene.camera.path.amplitude = place.camera.amplitude;
  scene.camera.path.frequency = kSeedLightFrequency;
  // A camera looking straight down or up: lookAt's +Y up is parallel to the view, so take -Z (the model's
  // back).
  const glm::vec3 view = scene.camera.target - scene.camera.position;
  if (!(glm::length(view) > 0.0f)) throw SceneError(path + ": --camera position and target coincide");
  if (!(glm::length(glm::cross(glm::normalize(view), scene.camera.up)) > 1e-6f))
    scene.camera.up = glm::vec3(0, 0, -1);
  char placed[320];
  if (!file_lights.empty() && !options.light)
    std::snprintf(placed, sizeof placed,
                  "placed by rule: scaled by %.6g (bounding radius %.6g file units -> %g), the model's %zu "
                  "point light(s) (KHR_lights_punctual); camera %s",
                  place.scale, kModelRadius / place.scale, kModelRadius, scene.point_lights.size(),
                  options.camera ? "by --camera" : "by rule");
  else
    std::snprintf(
        placed, sizeof placed,
        "placed by rule: scaled by %.6g (bounding radius %.6g file units -> %g), light %s at (%.6g, %.6g, "
        "%.6g), far %.6g; camera %s",
        place.scale, kModelRadius / place.scale, kModelRadius, options.light ? "by --light" : "by rule",
        place.light.base.x, place.light.base.y, place.light.base.z, place.light_far,
        options.camera ? "by --camera" : "by rule");
  scene.notes.push_back(path + ": " + placed);
}

}  // namespace

Scene load_model_scene(const std::string& path, const LoadOptions& options) {
  const ModelMesh m = read_model(path);
  Scene scene;
  scene.source = path;
  scene.name = std::filesystem::path(path).stem().string();
  scene.notes.insert(scene.notes.end(), m.notes.begin(), m.notes.end());

  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const MeshVertex& v : m.mesh) {
    lo = glm::min(lo, glm::dvec3(v.position));
    hi = glm::max(hi, glm::dvec3(v.position));
  }
  const ModelPlacement place = place_model(lo, hi, options, path);
  // The rebase remedy subtracts the first point light's base position, in double, as for scene files.
  if (options.rebase_origin)
    scene.origin = m.lights.empty() || options.light ? place.light.base : place.scale * m.lights[0].position;

  scene.vertices.reserve(m.mesh.size() + 6);
  add_baked_object(
      scene, scene.name, m.kind, m.mesh, [&](const glm::vec3& p) { return place.scale * glm::dvec3(p); },
      [&](size_t i) { return m.colors.empty() ? glm::vec3(0.8f) : m.colors[i]; });
  // make_plane is [-1, 1]^2 at y = 0, normal +Y: scaled and moved under the model.
  const glm::dvec3 floor_at(place.center.x, place.floor_y, place.center.z);
  add_baked_object(
      scene, "floor", "plane", make_plane(),
      [&](const glm::vec3& p) { return floor_at + place.floor_half_size * glm::dvec3(p); },
      [](size_t) { return glm::vec3(0.8f); });
  set_light_and_camera(scene, place, options, m.lights, path);
  return scene;
}

}  // namespace omnishadow::scene
