#include "backends/common/shadow_frame.h"

#include <algorithm>
#include <bit>
#include <tuple>

#include "backends/common/case_support.h"
#include "backends/common/frame_uniforms.h"
#include "backends/common/layouts.h"
#include "backends/common/view_culling.h"

namespace omnishadow::gpu {

ShadowFrame ShadowFramePlanner::prepare(const scene::Scene& scene, int frame, const CaseConfig& config,
                                        cube::DepthRange range, int face_size) {
  ShadowFrame f;
  f.frame = frame;
  f.uniforms = make_frame_uniforms(scene, frame, config, range);
  // The pass's target edge: the light's atlas tile, else the layout's layer (a paraboloid's is --cube x sqrt
  // 3).
  const int target = config.layout == Layout::atlas ? face_size : layer_size(config.layout, config.cube_size);
  f.uniforms.raster_knobs.x = float(config.cube_size) / float(target);
  // The light's position and range decide the cube's content, and the moving casters within its reach.
  // Exact float equality: a light that moves by one ulp renders again.
  f.reuse_cube = config.optimizations.static_cache && cube_light_ &&
                 *cube_light_ == f.uniforms.light_position &&
                 !cube::moved_caster_faces(scene, glm::vec3(*cube_light_), scene.light().near_plane,
                                           cube_light_->w, cube_frame_, frame);
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

uint8_t ShadowFramePlanner::stale_faces(const scene::Scene& scene, const glm::vec4& light, float near_plane,
                                        int frame) {
  uint8_t stale = 0;
  for (int face = 0; face < cube::kFaceCount; ++face) {
    FaceContent& c = faces_[size_t(face)];
    // Exact: a light that moved by one ulp is stale.
    const bool holds =
        c.frame >= 0 && c.light == light &&
        !((cube::moved_caster_faces(scene, glm::vec3(light), near_plane, light.w, c.frame, frame) >> face) &
          1u);
    if (holds) continue;
    stale |= uint8_t(1u << face);
    if (c.stale_since < 0) c.stale_since = frame;
  }
  return stale;
}

void ShadowFramePlanner::rendered(const ShadowFrame& f, const CaseConfig& config) {
  if (f.skipped()) return;
  cube_far_ = f.uniforms.light_position.w;
  written_ = true;
  // The faces the pass rewrote: its own passes' faces where each face has one, else all six (one layered
  // clear, an atlas block's clear, the moments blur over the whole cube); of those, the faces drawn now hold
  // this frame's light, the others are cleared.
  const uint8_t touched = refreshes_single_faces(config) ? f.pass_faces : cube::kAllFaces;
  for (int face = 0; face < cube::kFaceCount; ++face) {
    if (!((touched >> face) & 1u)) continue;
    const bool drawn = (f.view_faces >> face) & 1u;
    faces_[size_t(face)] = drawn ? FaceContent{f.frame, f.uniforms.light_position, -1} : FaceContent{};
  }
  // A cube with faces left out by view culling is not whole: a later view may need them.
  if (config.optimizations.static_cache) {
    if (f.view_faces == cube::kAllFaces) {
      cube_light_ = f.uniforms.light_position;
      cube_frame_ = f.frame;
    } else {
      cube_light_.reset();
    }
  }
}

LightFrames LightFramePlanner::prepare(scene::Scene& scene, int frame, const CaseConfig& config,
                                       cube::DepthRange range) {
  LightFrames f;
  f.camera = scene.camera.at(frame);
  if (atlas_) replan_atlas(f, scene, frame, config);
  for (size_t k = 0; k < planners_.size(); ++k) {
    scene::FocusLight focus(scene, static_cast<int>(k));
    f.lights.push_back(planners_[k].prepare(scene, frame, config, range, face_size(int(k), config)));
  }
  // Every light in one pass renders every light or none: one that moved makes the others render again.
  const bool all_reuse =
      std::all_of(f.lights.begin(), f.lights.end(), [](const ShadowFrame& s) { return s.reuse_cube; });
  if (config.update_budget_faces > 0) apply_update_budget(f, scene, frame, config);
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

void LightFramePlanner::replan_atlas(LightFrames& f, const scene::Scene& scene, int frame,
                                     const CaseConfig& config) {
  const int at = atlas::planned_frame(config, frame);
  if (at == planned_at_) return;
  atlas::Plan next = atlas::plan_after(config, scene, at, *atlas_, planned_at_);
  const std::vector<uint8_t> moved = atlas::moved_blocks(*atlas_, next);
  for (size_t k = 0; k < planners_.size() && k < moved.size(); ++k) {
    if (!moved[k]) continue;
    planners_[k].reset();
    ++f.atlas_relocated;
  }
  f.atlas_replanned = f.atlas_relocated > 0;
  atlas_ = std::move(next);
  planned_at_ = at;
}

// Units are faces where a face can be refreshed alone, else lights (their faces drawn as cost), taken by
// the frame their content went stale (then light, then face, so that the order is deterministic) while the
// budget lasts; the first that does not fit ends the frame's refreshes, so that no unit waits behind later
// ones: a unit waits at most ceil(units that can be stale / units a frame) - 1 frames. A light never written
// since configure renders whole, outside the budget (its map must hold defined values); so does a face the
// frame reads that holds nothing (culled to the view until now, as a walking camera or a moving lamp brings
// it in): alone where faces refresh alone, else with its whole light. That work is a first render, not a
// refresh: it leaves the budget and the wait bound to the stale faces.
void LightFramePlanner::apply_update_budget(LightFrames& f, const scene::Scene& scene, int frame,
                                            const CaseConfig& config) {
  struct Unit {
    int since, light, face, cost;  // face -1: the whole light
  };
  const bool single = refreshes_single_faces(config);
  std::vector<Unit> units;
  std::vector<uint8_t> refresh(f.lights.size(), 0);
  for (size_t k = 0; k < f.lights.size(); ++k) {
    ShadowFrame& s = f.lights[k];
    ShadowFramePlanner& p = planners_[k];
    if (s.skipped() || !p.written()) continue;  // out of view, or rendered whole this frame
    uint8_t empty = 0;
    for (int face = 0; face < cube::kFaceCount; ++face)
      if (p.faces()[size_t(face)].frame < 0) empty |= uint8_t(1u << face);
    empty &= s.view_faces;
    refresh[k] = single ? empty : (empty ? cube::kAllFaces : uint8_t{0});
    const float near_plane = scene.point_lights.at(k).near_plane;
    const uint8_t stale =
        p.stale_faces(scene, s.uniforms.light_position, near_plane, frame) & s.view_faces & ~refresh[k];
    int oldest = frame;
    for (int face = 0; face < cube::kFaceCount; ++face) {
      if (!((stale >> face) & 1u)) continue;
      const int since = p.faces()[size_t(face)].stale_since;
      if (single) units.push_back({since, int(k), face, 1});
      oldest = std::min(oldest, since);
    }
    if (!single && stale) units.push_back({oldest, int(k), -1, std::popcount(s.view_faces)});
  }
  std::sort(units.begin(), units.end(), [](const Unit& a, const Unit& b) {
    return std::tie(a.since, a.light, a.face) < std::tie(b.since, b.light, b.face);
  });
  int left = config.update_budget_faces;
  for (const Unit& u : units) {
    if (u.cost > left) break;
    left -= u.cost;
    refresh[size_t(u.light)] |= u.face < 0 ? cube::kAllFaces : uint8_t(1u << u.face);
  }
  for (size_t k = 0; k < f.lights.size(); ++k) {
    ShadowFrame& s = f.lights[k];
    if (s.skipped() || !planners_[k].written()) continue;
    if (!refresh[k]) {
      s.deferred = true;
      s.plan = {};
    } else if (single) {
      s.pass_faces = refresh[k] & s.view_faces;
      cube::keep_faces(s.plan, s.pass_faces);
    }
  }
}

std::vector<std::array<int, 6>> LightFramePlanner::face_frames() const {
  std::vector<std::array<int, 6>> out;
  for (const ShadowFramePlanner& p : planners_) {
    std::array<int, 6> frames{};
    for (int face = 0; face < cube::kFaceCount; ++face) frames[size_t(face)] = p.faces()[size_t(face)].frame;
    out.push_back(frames);
  }
  return out;
}

void LightFramePlanner::rendered(const LightFrames& f, const CaseConfig& config) {
  for (size_t k = 0; k < planners_.size() && k < f.lights.size(); ++k)
    planners_[k].rendered(f.lights[k], config);
}

}  // namespace omnishadow::gpu
