#pragma once
// The per-frame decisions both backends share: the uniform block, the shadow draw plan (per-face object
// lists, per-object face masks) and whether the cube rendered earlier can be reused (static caching).

#include <optional>

#include "backends/common/case_config.h"
#include "backends/common/cube_faces.h"
#include "backends/common/gpu_layout.h"
#include "backends/common/shadow_plan.h"
#include "scenes/scene.h"

namespace omnishadow::gpu {

struct ShadowFrame {
  FrameUniforms uniforms;
  cube::ShadowDrawPlan plan;  // empty when reuse_cube
  bool reuse_cube = false;    // static_cache and the cube already holds this light position and range
};

class ShadowFramePlanner {
 public:
  // After configure(): the cube's content is unknown.
  void reset() { cube_light_.reset(); }
  ShadowFrame prepare(const scene::Scene& scene, int frame, const CaseConfig& config, cube::DepthRange range);
  // The shadow pass of `f` has been submitted: with static caching, the cube now holds its light.
  void rendered(const ShadowFrame& f, const CaseConfig& config);
  // The light far plane of the cube's content (fit_range makes it per frame): read-back scales linear depth
  // by it.
  float cube_far() const { return cube_far_; }

 private:
  std::optional<glm::vec4> cube_light_;  // xyz position, w far: what the cached cube was rendered for
  float cube_far_ = 0.0f;
};

}  // namespace omnishadow::gpu
