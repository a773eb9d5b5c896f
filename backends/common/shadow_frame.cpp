#include "backends/common/shadow_frame.h"

#include <algorithm>

#include "backends/common/frame_uniforms.h"
#include "backends/common/view_culling.h"

namespace omnishadow::gpu {

ShadowFrame ShadowFramePlanner::prepare(const scene::Scene& scene, int frame, const CaseConfig& config,
                                        cube::DepthRange range, int face_size) {
  ShadowFrame f;
  f.uniforms = make_frame_uniforms(scene, frame, config, range);
  // Casters never move (scenes are baked at load), so the light's position and range decide the cube's
  // content. Exact float equality: a light that moves by one ulp renders again.
  f.reuse_cube =
      config.optimizations.static_cache && cube_light_ && *cube_light_ == f.uniforms.light_position;
  if (!f.reuse_cube) {
    f.plan = cube::plan_shadow_draws(scene, glm::vec3(f.uniforms.light_position), scene.light().near_plane,
                                     f.uniforms.light_position.w, config.optimizations.face_culling);
    if (!scene.has_point_light()) {  // no point light: the cube is only cleared (the harness runs six_pass
                                     // only)
      for (auto& list : f.plan.face_objects) list.clear();
      f.plan.reaching.clear();
      std::fill(f.plan.object_faces.begin(), f.plan.object_faces.end(), uint8_t{0});
      f.plan.empty_faces = 6;
    }
    f.view_faces = view_faces(scene, config, frame, f.uniforms.light_position.w, face_size);
    f.out_of_view = f.view_faces == 0 && written_;
    if (written_) f.pass_faces = f.view_faces;
    if (f.out_of_view)
      f.plan = {};
    else
      cube::keep_faces(f.plan, f.view_faces);
  }
  return f;
}

void ShadowFramePlanner::rendered(const ShadowFrame& f, const CaseConfig& config) {
  if (f.skipped()) return;
  cube_far_ = f.uniforms.light_position.w;
  written_ = true;
  // A cube with faces left out by view culling is not whole: a later view may need them.
  if (config.optimizations.static_cache) {
    if (f.view_faces == cube::kAllFaces)
      cube_light_ = f.uniforms.light_position;
    else
      cube_light_.reset();
  }
}

LightFrames LightFramePlanner::prepare(scene::Scene& scene, int frame, const CaseConfig& config,
                                       cube::DepthRange range) {
  LightFrames f;
  for (size_t k = 0; k < planners_.size(); ++k) {
    scene::FocusLight focus(scene, static_cast<int>(k));
    f.lights.push_back(planners_[k].prepare(scene, frame, config, range, face_size(int(k), config)));
  }
  // Every light in one pass renders every light or none: one that moved makes the others render again.
  const bool all_reuse =
      std::all_of(f.lights.begin(), f.lights.end(), [](const ShadowFrame& s) { return s.reuse_cube; });
  for (size_t k = 0; k < planners_.size(); ++k) {
    if (config.light_grouping == LightGrouping::all_lights && !all_reuse && f.lights[k].reuse_cube) {
      scene::FocusLight focus(scene, static_cast<int>(k));
      planners_[k].reset();
      f.lights[k] = planners_[k].prepare(scene, frame, config, range, face_size(int(k), config));
    }
    const FrameUniforms& u = f.lights[k].uniforms;
    glm::vec4 tile(0.0f);
    if (atlas_) {
      const atlas::Block& b = atlas_->lights[k];
      tile = glm::vec4(float(b.x), float(b.y), float(b.face_size), float(atlas::kBorder));
    }
    f.records.push_back({u.light_position, u.light_color, glm::vec4(u.moments_knobs.y, 0.0f, 0.0f, 0.0f),
                         tile, u.face_view_proj});
  }
  return f;
}

void LightFramePlanner::rendered(const LightFrames& f, const CaseConfig& config) {
  for (size_t k = 0; k < planners_.size() && k < f.lights.size(); ++k)
    planners_[k].rendered(f.lights[k], config);
}

}  // namespace omnishadow::gpu
