// The staleness sequence (--staleness-frames): what an update budget costs, frame by frame. The case renders
// frames 0..N-1 from a fresh start (a floor frame forgets every map), as a renderer would from its first
// frame; after each, what every face holds (Backend::face_frames) and each measured light's shadow against
// that frame's exact point-light visibility.

#include <algorithm>
#include <array>
#include <map>
#include <tuple>

#include "backends/common/layouts.h"
#include "backends/common/shadow_plan.h"
#include "backends/common/view_culling.h"
#include "bench/run/case_runner.h"

namespace omnishadow::bench {

namespace {

// The lights whose error the sequence measures: those the checks read, and every one whose path moves
// within the sequence (only those can hold an older position).
std::vector<int> sequence_lights(const std::vector<int>& checked, const scene::Scene& scene, int light_count,
                                 int frames) {
  std::vector<int> lights = checked;
  for (int k = 0; k < light_count && k < int(scene.point_lights.size()); ++k) {
    const bool moves = moves_within(scene.point_lights[size_t(k)].path, frames - 1);
    if (moves && std::find(lights.begin(), lights.end(), k) == lights.end()) lights.push_back(k);
  }
  std::sort(lights.begin(), lights.end());
  return lights;
}

// The faces of light `k` (in focus) that frame `t` reads: view culling's, planned as the backend plans them
// (its far: the scene's, or fitted), else all six.
uint8_t read_faces(const CaseResult& r, const scene::Scene& sc, int t, const glm::vec3& at, int k) {
  if (!r.config.optimizations.view_culling) return cube::kAllFaces;
  const float far_plane = r.config.optimizations.fit_range
                              ? cube::fitted_far(sc, at, sc.light().near_plane, sc.light().far_plane)
                              : sc.light().far_plane;
  const int face_size = r.atlas ? r.atlas->lights.at(size_t(k)).face_size : r.config.cube_size;
  return gpu::view_faces(sc, r.config, t, far_plane, face_size);
}

}  // namespace

void Harness::measure_staleness(CaseResult& r, Backend& b) {
  const int frames = options_.staleness_frames_for(r.config);
  scene::Scene& sc = const_cast<scene::Scene&>(scene_of(r.config));  // not a const object: focus only
  if (frames <= 0 || !sc.has_point_light()) return;
  // --no-accuracy: the faces and waits only, no error (no lights measured).
  const std::vector<int> lights =
      options_.accuracy ? sequence_lights(lights_to_check(r.config), sc, r.config.light_count, frames)
                        : std::vector<int>{};
  TruthOptions point = options_.truth;
  point.light_radius = 0.0f;  // the misclassified figure reads the point light's visibility only
  // A light's truth per position: the camera stands still and, in a scene without moving casters, so does
  // everything the world positions read back show, so a light that stands still keeps its truth. With moving
  // casters every frame is its own (pose: the frame, else -1).
  std::map<std::tuple<int, int, float, float, float>, Truth> truths;
  const bool moving = sc.has_moving_objects();
  const CubeReadBack cube = traits(r.config.layout).geometry.map == TexelMap::cube_faces
                                ? CubeReadBack::sampled
                                : CubeReadBack::full;
  std::vector<SequenceFrame> sequence;
  b.render(0, FrameKind::floor);  // every map cleared and forgotten: a fresh start
  for (int t = 0; t < frames; ++t) {
    b.render(t, FrameKind::check);
    SequenceFrame s{t, b.face_frames(), {}, 0.0, 0};
    if (s.face_frames.empty()) break;  // the backend keeps no record of its faces
    sc.pose(t);
    const reference::RayCaster& caster = truths_.caster(r.config, sc);
    double wrong = 0.0;
    for (int k = 0; k < r.config.light_count; ++k) {
      scene::FocusLight focus(sc, k);
      const glm::vec3 at = sc.light().path.at(t);
      s.read_faces.push_back(read_faces(r, sc, t, at, k));
      if (!options_.accuracy || std::find(lights.begin(), lights.end(), k) == lights.end()) continue;
      const Images images = b.read_back(cube, k);
      auto [it, cast] = truths.try_emplace({k, moving ? t : -1, at.x, at.y, at.z});
      if (cast) it->second = compute_truth(caster, sc, t, images, point);
      const Accuracy a = measure_accuracy(it->second, images);
      wrong += a.misclassified_percent * double(a.pixels);
      s.pixels += a.pixels;
    }
    s.misclassified_percent = s.pixels ? wrong / double(s.pixels) : 0.0;
    sequence.push_back(std::move(s));
  }
  sc.pose(options_.check_frame);  // as the case's other checks read it
  if (sequence.empty()) return;
  check_update_budget(r, sc, lights, sequence);
}

}  // namespace omnishadow::bench
