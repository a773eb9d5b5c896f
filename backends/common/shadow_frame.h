#pragma once
// The per-frame decisions both backends share: the uniform block, the shadow draw plan (per-face object
// lists, per-object face masks) and whether the cube rendered earlier can be reused (static caching).

#include <array>
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
  cube::ShadowDrawPlan plan;  // empty when skipped
  bool reuse_cube = false;    // static_cache and the cube already holds this light position and range
  // View culling (gpu::view_faces): the faces the lit frame may read; the plan draws only those, the others
  // are cleared. 0: the light's range misses the view, and once its map has been written (so that it holds
  // defined values, and Vulkan's layers their layout) it gets no pass at all (out_of_view).
  uint8_t view_faces = cube::kAllFaces;
  bool out_of_view = false;
  // The faces that get a pass of their own where each face has one (six_pass over cube faces): view_faces
  // once the map was written (a culled face keeps what it held, read by no visible pixel), else every face.
  uint8_t pass_faces = cube::kAllFaces;
  bool face_pass(int face) const { return (pass_faces >> face) & 1u; }
  // The update budget (CaseConfig::update_budget_faces) left every stale face of this light for a later
  // frame: no pass, the map keeps what it holds.
  bool deferred = false;
  bool skipped() const { return reuse_cube || out_of_view || deferred; }  // no pass this frame
  int frame = 0;  // the frame index it was prepared for
};

// What one face of a light's map holds: the frame whose light position it was rendered for (-1: nothing
// yet, or cleared), that light (xyz position, w far), and the first frame it was found stale since then.
struct FaceContent {
  int frame = -1;
  glm::vec4 light{0.0f};
  int stale_since = -1;
};

class ShadowFramePlanner {
 public:
  // After configure(): the cube's content is unknown.
  void reset() {
    cube_light_.reset();
    written_ = false;
    faces_ = {};
  }
  // face_size: the light's face (its atlas tile's, or the cube's), for view culling's texel margins and, in
  // an atlas, the uniforms' raster_knobs (--raster-perturb's step in the tile).
  ShadowFrame prepare(const scene::Scene& scene, int frame, const CaseConfig& config, cube::DepthRange range,
                      int face_size);
  // The shadow pass of `f` has been submitted: with static caching, the cube now holds its light.
  void rendered(const ShadowFrame& f, const CaseConfig& config);
  // The light far plane of the cube's content (fit_range makes it per frame): read-back scales linear depth
  // by it.
  float cube_far() const { return cube_far_; }
  bool written() const { return written_; }
  // The faces that do not hold `light` (xyz position, w far) as frame `frame` has it, each marked stale since
  // `frame` the first time it is found so: a face rendered for another position or range of its light, or one
  // a moving caster reached since (cube::moved_caster_faces; `scene` at any pose, near: the light's).
  uint8_t stale_faces(const scene::Scene& scene, const glm::vec4& light, float near_plane, int frame);
  const std::array<FaceContent, 6>& faces() const { return faces_; }

 private:
  std::optional<glm::vec4> cube_light_;  // xyz position, w far: what the cached cube was rendered for
  int cube_frame_ = -1;                  // and the frame whose casters it holds
  float cube_far_ = 0.0f;
  bool written_ = false;  // a pass has written the light's map since configure
  std::array<FaceContent, 6> faces_{};
};

// A frame of a case with CaseConfig::light_count point lights: each light's ShadowFrame (its uniforms, drawn
// into its own map), in the scene's order, and the lighting pass's records of them.
struct LightFrames {
  std::vector<ShadowFrame> lights;
  std::vector<PointLightRecord> records;
  scene::Camera camera;  // the one the frame is seen through (Camera::at): the clustered lists' view
  // Layout atlas with re-plans: this frame's tiles differ from the last frame's (LightFramePlanner::atlas()
  // has them; the records carry them already). The lights whose block changed render whole.
  bool atlas_replanned = false;
  int atlas_relocated = 0;  // how many lights' blocks changed
};

// One ShadowFramePlanner per light. The frame uniforms of light k are made with the scene's focus on light k
// (scene::FocusLight), so the one-light code (make_frame_uniforms, plan_shadow_draws) serves every light.
class LightFramePlanner {
 public:
  // `atlas`: layout atlas's plan as allocated at configure (atlas::plan_for; each light's record carries its
  // tiles). With re-plans (CaseConfig::atlas_replan_frames) prepare() moves to atlas::plan_at's tiles for the
  // frame, within the allocated width and height.
  void reset(int lights, std::optional<atlas::Plan> atlas = std::nullopt) {
    planners_.assign(static_cast<size_t>(lights), ShadowFramePlanner{});
    atlas_ = std::move(atlas);
    planned_at_ = 0;
  }
  LightFrames prepare(scene::Scene& scene, int frame, const CaseConfig& config, cube::DepthRange range);
  void rendered(const LightFrames& f, const CaseConfig& config);
  void forget() {
    for (ShadowFramePlanner& p : planners_) p.reset();
  }
  float cube_far(int light) const { return planners_.at(static_cast<size_t>(light)).cube_far(); }
  int lights() const { return static_cast<int>(planners_.size()); }
  int face_size(int light, const CaseConfig& config) const {
    return atlas_ ? atlas_->lights.at(size_t(light)).face_size : config.cube_size;
  }
  // The tiles of the frame last prepared (layout atlas; none otherwise).
  const std::optional<atlas::Plan>& atlas() const { return atlas_; }
  // Per light, the frame each face's content was rendered for (FaceContent::frame): what the staleness
  // checks hold to the lights' paths.
  std::vector<std::array<int, 6>> face_frames() const;

 private:
  // The update budget: which stale faces `f` refreshes (the oldest first), the others deferred.
  void apply_update_budget(LightFrames& f, const scene::Scene& scene, int frame, const CaseConfig& config);
  // Re-plans the atlas where `frame` is planned apart from the tiles in force; a light whose block changed
  // forgets its map (its texels are elsewhere now), so that it renders whole.
  void replan_atlas(LightFrames& f, const scene::Scene& scene, int frame, const CaseConfig& config);

  std::vector<ShadowFramePlanner> planners_;
  std::optional<atlas::Plan> atlas_;
  int planned_at_ = 0;  // the frame atlas_'s tiles were planned for
};

}  // namespace omnishadow::gpu
