#pragma once
// The exact references of a run, each computed once and shared by every case that asks for the same one: a
// ray caster per loaded scene, the cube and map texel truths per light, range and size, and the pixel truths
// per scene, frame and image size (a later truth takes the same-surface pixels of the first: TruthPrior).

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "backends/common/case_config.h"
#include "backends/reference/ray_caster.h"
#include "bench/truth/accuracy.h"
#include "bench/truth/cube_truth.h"
#include "bench/truth/map_truth.h"
#include "scenes/scene.h"

namespace omnishadow::bench {

// The key of a loaded scene: its name, and whether the rebase remedy moved it (truth caches are per key).
std::string scene_key(const std::string& name, bool rebase_origin, int tessellation = 1);
// The key of the scene a case renders (its name, load options and tessellation).
std::string scene_key(const CaseConfig& c);

class TruthCache {
 public:
  // `scene` is the one case `c` renders (its scene_key names it).
  const reference::RayCaster& caster(const CaseConfig& c, const scene::Scene& scene);
  // The cube's texels cast from `light` for a cube of `cube_size` over [near_plane, far_plane], with the
  // case's culling (two_sided) and layout (its texel map).
  const CubeTruth& cube_truth(const CaseConfig& c, const scene::Scene& scene, const glm::vec3& light,
                              float near_plane, float far_plane, int cube_size);
  const MapTruth& map_truth(const CaseConfig& c, const scene::Scene& scene, int frame, int map_size,
                            cube::DepthRange range);
  // The pixel truth of `images` (their world positions) at `frame`.
  const Truth& truth(const CaseConfig& c, const scene::Scene& scene, int frame, const Images& images,
                     const TruthOptions& options);

 private:
  std::map<std::string, std::unique_ptr<reference::RayCaster>> casters_;  // by scene
  std::map<std::string, CubeTruth> cube_truths_;  // by scene, light position, near, far and cube size
  std::map<std::string, MapTruth> map_truths_;    // by scene, frame, map size and depth range
  std::map<std::string, Truth> truths_;  // by scene, frame and positions fingerprint: shared by all its cases
  // Per scene, frame and image size: the first truth cast (its key in truths_) and the world positions it was
  // cast from, the prior every later truth of that scene takes its same-surface pixels from.
  std::map<std::string, std::pair<std::string, std::vector<float>>> truth_priors_;
};

}  // namespace omnishadow::bench
