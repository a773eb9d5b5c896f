#pragma once
// A scene holds only what shadows need: triangle geometry with a colour, lights and a camera.
// Units are world units; the light path is a function of the frame index (never wall-clock time), so any
// frame of any case can be reproduced bit for bit.

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace omnishadow::scene {

// Raised for every defect in a scene file; what() is one line naming the file and the JSON pointer.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Vertex {
  glm::vec3 position;  // world space (instances are baked at load; a moving object's as posed: Scene::pose)
  glm::vec3 normal;    // world space, unit length, pointing to the side that is lit
  glm::vec3 color;     // linear RGB albedo
};

// Light position as a function of the frame: position = base + amplitude * sin(frequency * t + phase),
// t = frame * seconds_per_frame. Seeds 000/001: base (0,0,0), amplitude (0,0,3), frequency 0.5, phase 0.
// A moving object's offset from where the file put it is the same function with base 0.
struct LightPath {
  glm::vec3 base{0.0f};
  glm::vec3 amplitude{0.0f};
  float frequency = 0.0f;  // radians per second of scene time
  float seconds_per_frame = 1.0f / 60.0f;
  float phase = 0.0f;  // radians: lamps of one row sway out of step (a light array's phase_step)
  glm::vec3 at(int frame) const;
  bool operator==(const LightPath&) const = default;
};
// The tutorials' sway (seeds 000/001), and that of lights placed by rule or by --light.
inline constexpr float kSeedLightFrequency = 0.5f;  // rad/s

// One scene object after baking: a contiguous range of triangles in Scene::vertices.
struct Object {
  std::string name;
  std::string kind;  // box, plane, sphere, obj, gltf
  uint32_t first_vertex = 0;
  uint32_t vertex_count = 0;
  bool cull_back_faces = false;  // closed convex meshes seen from outside; false for rooms and quads
  glm::vec3 bounds_min{0.0f};    // as posed (Scene::pose): where the scene's last posed frame put it
  glm::vec3 bounds_max{0.0f};
  // A moving caster: translated by motion.at(frame) (base 0) from where the file put it (rest_bounds_*), a
  // function of the frame index like a light's path. A path without amplitude stands still.
  LightPath motion;
  glm::vec3 rest_bounds_min{0.0f};
  glm::vec3 rest_bounds_max{0.0f};
  bool moves() const { return motion.amplitude != glm::vec3(0.0f); }
  glm::vec3 offset_at(int frame) const { return moves() ? motion.at(frame) : glm::vec3(0.0f); }
  // Its bounds at `frame`, whatever frame the scene is posed at.
  glm::vec3 bounds_min_at(int frame) const {
    return moves() ? rest_bounds_min + offset_at(frame) : bounds_min;
  }
  glm::vec3 bounds_max_at(int frame) const {
    return moves() ? rest_bounds_max + offset_at(frame) : bounds_max;
  }
};

struct PointLight {
  LightPath path;
  float near_plane = 1.0f;  // world units; the 90-degree face projections use these
  float far_plane = 25.0f;
  glm::vec3 color{0.3f};  // the point-shadow tutorial lighting: lightColor 0.3, ambient 0.3 * albedo
  bool operator==(const PointLight&) const = default;
};
// A bound on what a file can ask for (a light array of 10x10x10 lamps); the matrix's --light-count picks how
// many of them a case renders.
inline constexpr int kMaxPointLights = 1024;

// Lights that need no cube: each gets one 2D map (scene::Scene::map_lights), rendered in one plain pass.
enum class MapLightType { spot, directional };
struct MapLight {
  MapLightType type = MapLightType::spot;
  LightPath path;                          // spot: its position over time; unused for directional
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // unit; the way the light travels (spot: where it points)
  float cone_degrees = 60.0f;              // spot: full cone angle = the map's field of view (square map)
  float near_plane = 0.1f;                 // spot only; a directional map's range is fitted to the scene
  float far_plane = 25.0f;
  glm::vec3 color{0.3f};
  bool cull_front_faces =
      false;  // the directional notes' peter-panning fix: closed objects render their back faces only
};
inline constexpr int kMaxMapLights = 4;

struct Camera {
  glm::vec3 position{0.0f, 0.0f, 3.0f};
  glm::vec3 target{0.0f, 0.0f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fov_y_degrees = 45.0f;
  float near_plane = 0.1f;
  float far_plane = 100.0f;
  int width = 800;
  int height = 600;
  // A moving camera (a walk through the scene): position and target translated together by path.at(frame)
  // (base 0), a function of the frame index like a moving caster's, so it keeps its direction and up. A path
  // without amplitude stands still.
  LightPath path;
  bool moves() const { return path.amplitude != glm::vec3(0.0f); }
  // The camera frame `frame` sees through: this one moved along its path, as a still camera. Whatever draws,
  // culls or checks a frame's lit image reads the camera there, never `position` itself.
  Camera at(int frame) const;
};

struct Scene {
  // World = stored + origin. Zero unless loaded with rebase_origin: positions are then stored relative to the
  // light, computed in double before the conversion to float, so a scene far from the origin keeps its
  // precision.
  glm::dvec3 origin{0.0};
  std::string name;    // file stem: "room"
  std::string source;  // file the scene came from, for error messages
  // What loading left out, one line each (a glTF model's point and line primitives): said once when the scene
  // is first loaded for a run.
  std::vector<std::string> notes;
  std::vector<Vertex> vertices;  // non-indexed triangle list, all objects back to back
  std::vector<Object> objects;
  // The point lights in file order, each with its own shadow map (a cube, or its layers or tiles of a shared
  // texture); none when the scene only holds spot/directional lights. A case renders the first
  // CaseConfig::light_count of them.
  std::vector<PointLight> point_lights{PointLight{}};
  bool has_point_light() const { return !point_lights.empty(); }
  // The point light in focus, the first unless FocusLight says otherwise: the one every one-light case
  // renders, and the one the one-light code (frame uniforms, draw plans, truths) sees while a many-light
  // case renders or checks its lights one by one. A scene without point lights still has a cube, only
  // cleared, whose planes are a default PointLight's: that is what it returns there.
  const PointLight& light() const;
  int focus_light = 0;               // an index into point_lights; set through FocusLight
  std::vector<MapLight> map_lights;  // in file order, at most kMaxMapLights
  Camera camera;
  uint64_t triangle_count() const { return vertices.size() / 3; }

  // Moving casters (Object::motion). pose(frame) puts every moving object where frame `frame` has it: its
  // vertices are its rest positions (kept on the first pose) plus the offset, computed afresh each time so
  // that a frame's geometry never depends on the frames posed before it; its bounds likewise. Whatever
  // renders or casts rays at a frame poses the scene at that frame first; a scene without moving objects
  // ignores it.
  bool has_moving_objects() const;
  void pose(int frame);
  void put_at_rest();                     // every moving object where the file put it (posed_frame -1)
  int posed_frame = -1;                   // -1: at rest, as loaded
  std::vector<glm::vec3> rest_positions;  // per vertex; filled on the first pose of a scene with movers
};

// Puts light `light` of `scene` in focus (Scene::light()) for the guard's lifetime.
class FocusLight {
 public:
  FocusLight(Scene& scene, int light) : scene_(scene), before_(scene.focus_light) {
    scene.focus_light = light;
  }
  ~FocusLight() { scene_.focus_light = before_; }
  FocusLight(const FocusLight&) = delete;
  FocusLight& operator=(const FocusLight&) = delete;

 private:
  Scene& scene_;
  int before_;
};

// 2^24 vertices (5.6 M triangles, ~600 MB baked): 50x the heavy scene, and a bound on what a file can ask
// for.
inline constexpr uint64_t kMaxSceneVertices = uint64_t(1) << 24;

// `--light X,Y,Z[,AX,AY,AZ]`: the point light placed by hand, in world units of the file (before any rebase):
// position = base + amplitude * sin(0.5 t), the seeds' frequency; no amplitude = a light standing still.
struct LightPlacement {
  glm::dvec3 base{0.0};
  glm::vec3 amplitude{0.0f};
};
// `--camera X,Y,Z[,TX,TY,TZ[,AX,AY,AZ]]`: the camera's position, the point it looks at (default: the scene's
// target), and its sway: both translated by amplitude * sin(0.5 t), the seeds' frequency; no amplitude = a
// camera standing still.
struct CameraPlacement {
  glm::dvec3 position{0.0};
  std::optional<glm::dvec3> target;
  glm::vec3 amplitude{0.0f};
};

struct LoadOptions {
  // The far-from-origin remedy: subtract the light's position (the point light's, else the first spot
  // light's) from every position in double precision before baking to float.
  bool rebase_origin = false;
  // Overrides of the file's point light and camera (a scene file's, or a model's placement rule). The light's
  // near and far planes stay the file's; a model's are fitted to the placed light.
  std::optional<LightPlacement> light;
  std::optional<CameraPlacement> camera;
};

// Whether `path` names a model (.obj, .gltf, .glb, any case) rather than a scene file: load_scene_file runs a
// model as a scene of its own (scenes/model_scene.h).
bool is_model_file(const std::string& path);

// Loads and validates a scene file, or a model by the placement rule (is_model_file). Throws
// SceneError("file: /objects/3/scale: must be > 0") on any defect.
Scene load_scene_file(const std::string& path, const LoadOptions& options = {});
// Same from text already in memory; `source` is only used to name errors.
Scene load_scene_text(const std::string& text, const std::string& source, const LoadOptions& options = {});

}  // namespace omnishadow::scene
