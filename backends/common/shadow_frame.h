#pragma once
// The per-frame decisions both backends share: the uniform block, the shadow draw plan (per-face object
// lists, per-object face masks) and whether the cube rendered earlier can be reused (static caching).

#include <optional>
#include <vector>

#include "backends/common/atlas.h"
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

// A frame of a case with CaseConfig::light_count point lights: each light's ShadowFrame (its uniforms, drawn
// into its own map), in the scene's order, and the lighting pass's records of them.
struct LightFrames {
  std::vector<ShadowFrame> lights;
  std::vector<PointLightRecord> records;
};

// One ShadowFramePlanner per light. The frame uniforms of light k are made with the scene's focus on light k
// (scene::FocusLight), so the one-light code (make_frame_uniforms, plan_shadow_draws) serves every light.
class LightFramePlanner {
 public:
  // `atlas`: layout atlas's plan, made once at configure (each light's record carries its tiles).
  void reset(int lights, std::optional<atlas::Plan> atlas = std::nullopt) {
    planners_.assign(static_cast<size_t>(lights), ShadowFramePlanner{});
    atlas_ = std::move(atlas);
  }
  LightFrames prepare(scene::Scene& scene, int frame, const CaseConfig& config, cube::DepthRange range);
  void rendered(const LightFrames& f, const CaseConfig& config);
  void forget() {
    for (ShadowFramePlanner& p : planners_) p.reset();
  }
  float cube_far(int light) const { return planners_.at(static_cast<size_t>(light)).cube_far(); }
  int lights() const { return static_cast<int>(planners_.size()); }

 private:
  std::vector<ShadowFramePlanner> planners_;
  std::optional<atlas::Plan> atlas_;
};

}  // namespace omnishadow::gpu
