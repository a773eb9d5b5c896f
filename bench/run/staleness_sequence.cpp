// The staleness sequence (--staleness-frames): what an update budget costs, frame by frame. The case renders
// frames 0..N-1 from a fresh start (a floor frame forgets every map), as a renderer would from its first
// frame; after each, what every face holds (Backend::face_frames) and each measured light's shadow against
// that frame's exact point-light visibility.

#include <algorithm>
#include <array>
#include <map>

#include "backends/common/atlas.h"
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

// The faces of the light in focus that frame `t` reads: view culling's, planned as the backend plans them
// (its far: the scene's, or fitted; face_size its tiles' at t), else all six.
uint8_t read_faces(const CaseResult& r, const scene::Scene& sc, int t, const glm::vec3& at, int face_size) {
  if (!r.config.optimizations.view_culling) return cube::kAllFaces;
  const float far_plane = r.config.optimizations.fit_range
                              ? cube::fitted_far(sc, at, sc.light().near_plane, sc.light().far_plane)
                              : sc.light().far_plane;
  return gpu::view_faces(sc, r.config, t, far_plane, face_size);
}

// Layout atlas: the tiles in force at each frame of the sequence (atlas::plan_at, planned again only where a
// re-plan falls), and which lights' blocks the frame moved.
class SequenceTiles {
 public:
  SequenceTiles(const CaseConfig& c, const scene::Scene& sc) : config_(c), scene_(sc) {}
  // Moves to frame t; the lights whose block differs from the frame before's (none at the first frame).
  std::vector<uint8_t> advance(int t) {
    if (config_.layout != Layout::atlas) return {};
    const int at = atlas::planned_frame(config_, t);
    if (!plan_.lights.empty() && at == planned_at_) return {};
    atlas::Plan next = plan_.lights.empty() ? atlas::plan_at(config_, scene_, t)
                                            : atlas::plan_after(config_, scene_, at, plan_, planned_at_);
    std::vector<uint8_t> moved = atlas::moved_blocks(plan_, next);  // none at the first frame
    plan_ = std::move(next);
    planned_at_ = at;
    return moved;
  }
  int face_size(int k) const {
    return plan_.lights.empty() ? config_.cube_size : plan_.lights.at(size_t(k)).face_size;
  }

 private:
  const CaseConfig& config_;
  const scene::Scene& scene_;
  atlas::Plan plan_;  // no lights until the first frame, and outside layout atlas
  int planned_at_ = 0;
};

// Whether a moving caster moved between frames `then` and `now` within `range` of `light` (its box at either
// frame). Visibility of a point within range cannot change otherwise: the segment from it to the light lies
// within the range.
bool caster_moved_within(const scene::Scene& sc, const glm::vec3& light, float range, int then, int now) {
  for (const scene::Object& o : sc.objects) {
    if (!o.moves() || o.offset_at(then) == o.offset_at(now)) continue;
    for (int f : {then, now})
      if (glm::distance(glm::clamp(light, o.bounds_min_at(f), o.bounds_max_at(f)), light) <= range)
        return true;
  }
  return false;
}

// A light's last truth of the sequence, and what it was cast for.
struct LastCast {
  int frame = -1;
  glm::vec3 light{0.0f};
  Truth truth;
  std::vector<float> positions;
};

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
  // Each light's truth takes from its last one every pixel that shows the same surface point, where neither
  // the light nor a caster within its range moved in between: a still lamp far from the moving casters is
  // cast once, and one they pass recast only where the image changed. A point's visibility from a point
  // light does not depend on the camera, so a moving camera only recasts the pixels that show other points.
  std::map<int, LastCast> last;
  const CubeReadBack cube = traits(r.config.layout).geometry.map == TexelMap::cube_faces
                                ? CubeReadBack::sampled
                                : CubeReadBack::full;
  std::vector<SequenceFrame> sequence;
  SequenceTiles tiles(r.config, sc);
  b.render(0, FrameKind::floor);  // every map cleared and forgotten: a fresh start
  for (int t = 0; t < frames; ++t) {
    b.render(t, FrameKind::check);
    SequenceFrame s{t, b.face_frames(), {}, 0.0, 0, tiles.advance(t)};
    if (s.face_frames.empty()) break;  // the backend keeps no record of its faces
    sc.pose(t);
    const reference::RayCaster& caster = truths_.caster(r.config, sc);
    double wrong = 0.0;
    for (int k = 0; k < r.config.light_count; ++k) {
      scene::FocusLight focus(sc, k);
      const glm::vec3 at = sc.light().path.at(t);
      s.read_faces.push_back(read_faces(r, sc, t, at, tiles.face_size(k)));
      if (!options_.accuracy || std::find(lights.begin(), lights.end(), k) == lights.end()) continue;
      const Images images = b.read_back(cube, k);
      LastCast& before = last[k];
      TruthPrior prior;
      if (before.frame >= 0 && before.light == at &&
          !caster_moved_within(sc, at, sc.light().far_plane, before.frame, t))
        prior = {&before.truth, &before.positions};
      Truth truth = compute_truth(caster, sc, t, images, point, prior);
      const Accuracy a = measure_accuracy(truth, images);
      before = {t, at, std::move(truth), images.world_position};
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
