#include "bench/truth/truth_cache.h"

#include <cstdio>
#include <stdexcept>

#include "backends/common/layouts.h"

namespace omnishadow::bench {

// Scenes are cached per name and load option: the rebased room is another scene.
std::string scene_key(const std::string& name, bool rebase_origin, int tessellation) {
  return name + (rebase_origin ? "#rebase" : "") +
         (tessellation != 1 ? "#t" + std::to_string(tessellation) : "");
}
std::string scene_key(const CaseConfig& c) {
  return scene_key(c.scene, c.remedies.rebase_origin, c.tessellation);
}

namespace {

// The key of what a truth of `scene` casts against: its moving casters' pose, where it has any.
std::string posed_key(const CaseConfig& c, const scene::Scene& scene) {
  return scene.has_moving_objects() ? scene_key(c) + "#f" + std::to_string(scene.posed_frame) : scene_key(c);
}

// A truth of frame `frame` needs the scene posed there: one cast against another pose would pass or fail the
// renders for the wrong reason.
void require_pose(const scene::Scene& scene, int frame) {
  if (scene.has_moving_objects() && scene.posed_frame != frame)
    throw std::logic_error("truth of frame " + std::to_string(frame) + " asked of scene " + scene.name +
                           " posed at frame " + std::to_string(scene.posed_frame));
}

}  // namespace

const reference::RayCaster& TruthCache::caster(const CaseConfig& c, const scene::Scene& scene) {
  auto& caster = casters_[posed_key(c, scene)];
  if (!caster) caster = std::make_unique<reference::RayCaster>(scene);
  return *caster;
}

const CubeTruth& TruthCache::cube_truth(const CaseConfig& c, const scene::Scene& scene,
                                        const glm::vec3& light, float near_plane, float far_plane,
                                        int cube_size) {
  char key[256];
  const TexelGeometry& geometry = traits(c.layout).geometry;
  std::snprintf(key, sizeof key, "%s/%.9g,%.9g,%.9g/%.9g/%.9g/%d/%d/%d", posed_key(c, scene).c_str(), light.x,
                light.y, light.z, near_plane, far_plane, cube_size, int(c.remedies.two_sided),
                int(geometry.map));
  auto it = cube_truths_.find(key);
  if (it == cube_truths_.end())
    it = cube_truths_
             .emplace(key, compute_cube_truth(caster(c, scene), scene, light, near_plane, far_plane,
                                              cube_size, c.remedies.two_sided, geometry))
             .first;
  return it->second;
}

const MapTruth& TruthCache::map_truth(const CaseConfig& c, const scene::Scene& scene, int frame, int map_size,
                                      cube::DepthRange range) {
  require_pose(scene, frame);
  const std::string key = scene_key(c) + "/" + std::to_string(frame) + "/" + std::to_string(map_size) + "/" +
                          std::to_string(int(range));
  auto it = map_truths_.find(key);
  if (it == map_truths_.end())
    it = map_truths_.emplace(key, compute_map_truth(caster(c, scene), scene, frame, map_size, range)).first;
  return it->second;
}

// One truth per scene and frame, whichever API or technique asks: identical positions share it whole, and
// positions that differ by rounding (the other API's) share every pixel on the same surface point, cast again
// elsewhere.
const Truth& TruthCache::truth(const CaseConfig& c, const scene::Scene& scene, int frame,
                               const Images& images, const TruthOptions& options) {
  require_pose(scene, frame);
  // Per point light: a many-light case's checks put each light in the scene's focus in turn.
  const std::string shared = scene_key(c) + "/" + std::to_string(frame) + "/" + std::to_string(images.width) +
                             "x" + std::to_string(images.height) + "/L" + std::to_string(scene.focus_light);
  std::string key = shared + "/" + std::to_string(positions_fingerprint(images));
  auto it = truths_.find(key);
  if (it != truths_.end()) return it->second;
  auto prior = truth_priors_.find(shared);
  TruthPrior from;
  if (prior != truth_priors_.end()) from = {&truths_.at(prior->second.first), &prior->second.second};
  const Truth& made =
      truths_.emplace(key, compute_truth(caster(c, scene), scene, frame, images, options, from))
          .first->second;
  if (prior == truth_priors_.end()) truth_priors_.emplace(shared, std::make_pair(key, images.world_position));
  return made;
}

}  // namespace omnishadow::bench
