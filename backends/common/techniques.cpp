#include "backends/common/techniques.h"

#include <bit>

#include "backends/common/layouts.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/view_culling.h"

namespace omnishadow {

ShadowPassDraws shadow_pass_draws(const CaseConfig& config, const cube::ShadowDrawPlan& plan,
                                  size_t object_count) {
  const TechniqueTraits& t = traits(config.technique);
  const bool cull = config.optimizations.face_culling, view = config.optimizations.view_culling;
  ShadowPassDraws out;
  out.count =
      t.passes == 6 ? traits(config.layout).geometry.layers : t.passes;  // one pass per face, or per layer
  if (t.passes == 6) {  // the plan's per-face lists hold every object when culling is off
    for (size_t f = 0; f < static_cast<size_t>(out.count); ++f)
      for (uint32_t object : plan.face_objects[f]) out.draws[f].push_back({object, t.instances, 0});
    return out;
  }
  std::vector<ObjectDraw>& draws = out.draws[0];
  // Every light in one pass: vs_layer draws each object once with an instance per light and face; the
  // geometry shader's invocations route it to every light (one instance).
  const uint32_t lights =
      config.light_grouping == LightGrouping::all_lights && t.stages == ShadowStages::vertex
          ? uint32_t(config.light_count)
          : 1u;
  if (!cull && !view) {
    for (uint32_t i = 0; i < object_count; ++i) draws.push_back({i, t.instances * lights, 0});
    return out;
  }
  // View culling's faces reach the geometry shaders (and nv_swizzle's) through the draw's mask.
  const bool view_mask = view && gpu::culls_faces_to_view(config);
  for (uint32_t object : plan.reaching) {
    const uint8_t mask = plan.object_faces[object];
    if (t.culling != CullingForm::per_object_masks) {
      draws.push_back({object, t.instances, view_mask ? mask : uint8_t{0}});
      continue;
    }
    draws.push_back({object, static_cast<uint32_t>(std::popcount(mask)), mask});
  }
  return out;
}

ShadowDraw shadow_draw(const CaseConfig& c) {
  const TechniqueTraits& t = traits(c.technique);
  if (t.stages == ShadowStages::task_mesh)
    return c.emulate_mesh_shader ? ShadowDraw::emulated_mesh_tasks : ShadowDraw::mesh_tasks;
  if (t.feature == TechniqueFeature::viewport_swizzle && !c.emulate_nv_swizzle)
    return ShadowDraw::swizzled_viewports;
  return ShadowDraw::vertex_draws;
}

uint32_t mesh_lights(const CaseConfig& c) {
  return c.light_grouping == LightGrouping::all_lights ? uint32_t(c.light_count) : 1u;
}

bool reversed_depth_test(const CaseConfig& c) {
  return c.technique == Technique::nv_swizzle && !traits(c.storage).fragment_depth;
}

}  // namespace omnishadow
