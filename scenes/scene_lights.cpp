// Light parsing for scene files; the format is documented in scenes/README.md.

#include "scenes/scene_lights.h"

#include <cmath>

namespace omnishadow::scene {

glm::vec3 LightPath::at(int frame) const {
  float t = static_cast<float>(frame) * seconds_per_frame;
  return base + amplitude * std::sin(frequency * t + phase);
}

const PointLight& Scene::light() const {
  static const PointLight kClearedCube;
  return point_lights.empty() ? kClearedCube : point_lights.at(static_cast<size_t>(focus_light));
}

namespace detail {

LightPath parse_path_fields(const Node& p, LightPath path) {
  p.expect_object({"amplitude", "frequency", "seconds_per_frame", "phase"});
  if (p.has("amplitude")) path.amplitude = p.at("amplitude").vec3();
  if (p.has("frequency")) path.frequency = static_cast<float>(p.at("frequency").number());
  if (p.has("seconds_per_frame"))
    path.seconds_per_frame = static_cast<float>(p.at("seconds_per_frame").number_in(0, 3600));
  if (p.has("phase")) path.phase = static_cast<float>(p.at("phase").number_in(-1000, 1000));
  return path;
}

namespace {

LightPath parse_path(const Node& n, const glm::dvec3& origin) {
  LightPath path;
  path.base = glm::vec3(-origin);
  if (n.has("position")) path.base = n.at("position").position(origin);
  if (n.has("path")) path = parse_path_fields(n.at("path"), path);
  return path;
}

glm::vec3 unit_direction(const Node& n) {
  glm::vec3 d = n.vec3();
  if (!(glm::length(d) > 0.0f)) n.fail("direction must not be zero");
  return glm::normalize(d);
}

MapLight parse_map_light(const Node& n, const std::string& type, const glm::dvec3& origin) {
  MapLight l;
  l.type = type == "spot" ? MapLightType::spot : MapLightType::directional;
  if (l.type == MapLightType::spot) {
    n.expect_object({"type", "position", "path", "direction", "cone_degrees", "near", "far", "color",
                     "cull_front_faces"});
    l.path = parse_path(n, origin);
    if (n.has("cone_degrees")) l.cone_degrees = static_cast<float>(n.at("cone_degrees").number_in(1, 170));
    if (n.has("near")) l.near_plane = static_cast<float>(n.at("near").number_in(1e-9, 1e30));
    if (n.has("far")) l.far_plane = static_cast<float>(n.at("far").number_in(1e-9, 1e30));
    if (l.far_plane <= l.near_plane) n.at("far").fail("far must be greater than near");
  } else {
    n.expect_object({"type", "direction", "color", "cull_front_faces"});
  }
  l.direction = unit_direction(n.at("direction"));
  if (n.has("color")) l.color = n.at("color").vec3();
  if (n.has("cull_front_faces")) l.cull_front_faces = n.at("cull_front_faces").boolean();
  return l;
}

PointLight parse_light(const Node& n, const glm::dvec3& origin) {
  n.expect_object({"type", "position", "path", "near", "far", "color"});
  PointLight l;
  if (n.has("type") && n.at("type").string() != "point")
    n.at("type").fail("\"light\" is the point light; spot and directional lights go in \"lights\"");
  l.path = parse_path(n, origin);
  if (n.has("near")) l.near_plane = static_cast<float>(n.at("near").number_in(1e-9, 1e30));
  if (n.has("far")) l.far_plane = static_cast<float>(n.at("far").number_in(1e-9, 1e30));
  if (l.far_plane <= l.near_plane) n.at("far").fail("far must be greater than near");
  if (n.has("color")) l.color = n.at("color").vec3();
  return l;
}

}  // namespace

void parse_lights(const Node& root, Scene& scene) {
  scene.point_lights.clear();
  if (root.has("light") && root.has("lights"))
    root.at("lights").fail("give \"light\" or \"lights\", not both");
  if (!root.has("lights")) {
    scene.point_lights.push_back(parse_light(root.at("light"), scene.origin));
    return;
  }
  Node lights = root.at("lights");
  if (!lights.value().is_array() || lights.value().empty())
    lights.fail("expected a non-empty array of lights");
  for (size_t i = 0; i < lights.value().size(); ++i) {
    Node l = lights.at(i);
    if (!l.value().is_object()) l.fail("expected an object");
    std::string type = l.has("type") ? l.at("type").string() : "point";
    if (type == "point") {
      if (scene.point_lights.size() == size_t(kMaxPointLights))
        l.fail("at most " + std::to_string(kMaxPointLights) + " point lights per scene");
      scene.point_lights.push_back(parse_light(l, scene.origin));
    } else if (type == "spot" || type == "directional") {
      if (scene.map_lights.size() == kMaxMapLights)
        l.fail("at most " + std::to_string(kMaxMapLights) + " spot/directional lights per scene");
      scene.map_lights.push_back(parse_map_light(l, type, scene.origin));
    } else {
      l.at("type").fail("unknown light type '" + type + "' (valid: point, spot, directional)");
    }
  }
}

}  // namespace detail
}  // namespace omnishadow::scene
