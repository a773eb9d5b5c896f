#include "backends/common/case_support.h"

#include <optional>
#include <string>

#include "backends/common/cube_faces.h"
#include "backends/common/layouts.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"

namespace omnishadow {

namespace {
// Each moments knob only means something to the filters that read it (parse_moments_tuning's list).
Support moments_tuning_support(Filter filter, const MomentsTuning& t) {
  const MomentsTuning d;
  const std::optional<Storage> own = traits(filter).own_storage;
  const MomentKind kind = own ? traits(*own).moments : MomentKind::none;
  const std::string name(to_string(filter));
  if (t.bleed_reduction != d.bleed_reduction && kind != MomentKind::vsm && kind != MomentKind::evsm &&
      kind != MomentKind::msm)
    return {
        false,
        "bleed reduction (lbr) applies to the Chebyshev and Hamburger bounds (vsm, evsm2, evsm4, msm), not " +
            name};
  if (t.exponent_fraction != d.exponent_fraction && kind != MomentKind::esm && kind != MomentKind::evsm)
    return {false, "an exponent (exp) belongs to the warped moments (esm, evsm2, evsm4), not " + name};
  if (t.floor_scale != d.floor_scale && kind != MomentKind::vsm && kind != MomentKind::msm)
    return {false, "a variance floor or moment bias (floor) belongs to vsm and msm, not " + name};
  if (t.world_units && kind != MomentKind::vsm)
    return {false,
            "world-unit distances (world) are a vsm storage variant (the warps and msm's bias assume z in "
            "[0, 1]), not " +
                name};
  return {};
}
// Layout atlas routes faces by viewport; --atlas-tiles belongs to it alone.
Support atlas_support(const CaseConfig& c) {
  if (c.atlas_hysteresis_octaves != 0.0f && !c.atlas_replan_frames)
    return {false,
            "--atlas-hysteresis holds tile sizes from one re-plan to the next: it needs --atlas-replan"};
  if (c.layout == Layout::atlas) {
    const std::string technique(to_string(c.technique));
    if (c.technique == Technique::multiview || c.technique == Technique::mesh_shader)
      return {
          false,
          "atlas routes each face to its tile by viewport (one layer): six_pass, geometry_shader, "
          "geometry_shader_instanced, vs_layer and nv_swizzle do; " +
              technique +
              (c.technique == Technique::multiview ? " routes by view (multiview has one viewport for all)"
                                                   : " routes each primitive by layer here")};
    if (c.light_grouping == LightGrouping::all_lights)
      return {false, "every light in one pass into an atlas needs 6 viewports a light (16 on most devices)"};
    if (c.shadow_budget_texels && c.atlas_tiles != AtlasTiles::by_coverage)
      return {false, "--shadow-budget sizes the tiles by coverage (--atlas-tiles by_coverage), not " +
                         std::string(to_string(c.atlas_tiles))};
    if (c.atlas_replan_frames && c.atlas_tiles == AtlasTiles::uniform)
      return {false,
              "--atlas-replan plans the tiles again by distance or coverage (--atlas-tiles by_distance, "
              "by_coverage); uniform tiles never change"};
  } else if (c.atlas_tiles != AtlasTiles::uniform || c.atlas_replan_frames) {
    if (c.atlas_replan_frames && c.atlas_tiles == AtlasTiles::uniform)
      return {false, "--atlas-replan plans an atlas's tiles again; layout " +
                         std::string(to_string(c.layout)) + " gives every light --cube"};
    return {false, "--atlas-tiles " + std::string(to_string(c.atlas_tiles)) +
                       " sizes an atlas's tiles; layout " + std::string(to_string(c.layout)) +
                       " gives every light --cube"};
  }
  return {};
}

// Every light in one pass: vs_layer's instances, the geometry shader's invocations or mesh_shader's task
// workgroups (one per meshlet group and light).
Support all_lights_support(const CaseConfig& c) {
  if (c.light_grouping == LightGrouping::all_lights) {
    const bool routes_faces =
        c.technique == Technique::geometry_shader || c.technique == Technique::mesh_shader;
    if (c.technique != Technique::vs_layer && !routes_faces)
      return {
          false,
          "every light in one pass is built for vs_layer (an instance per light and face), "
          "geometry_shader (32 invocations, each routing a triangle to two lights' faces) and mesh_shader "
          "(a task workgroup per meshlet group and light); " +
              std::string(to_string(c.technique)) + " renders per light"};
    if (routes_faces && traits(c.layout).geometry.map != TexelMap::cube_faces)
      return {false, "every light in one " + std::string(to_string(c.technique)) +
                         " pass routes each light's six cube faces; " + std::string(to_string(c.layout)) +
                         " has layers of its own"};
    if (c.technique == Technique::geometry_shader && c.light_count > kAllLightsGeometryMaxLights)
      return {false, "every light in one geometry shader pass reaches " +
                         std::to_string(kAllLightsGeometryMaxLights) +
                         " lights (32 invocations, the least every device allows, of two lights each), not " +
                         std::to_string(c.light_count)};
    if (c.optimizations.face_culling)
      return {
          false,
          routes_faces
              ? "face culling with every light in one pass: " + std::string(to_string(c.technique)) +
                    " culls per light and face already"
              : "face culling with every light in one pass: the per-object masks cover one light's faces"};
    if (c.moments.world_units)
      return {false,
              "moments in world units with every light in one pass: one clear value for every light's far"};
    if (c.optimizations.view_culling)
      return {false,
              "view culling with every light in one pass: the pass draws every light's faces (cull per light "
              "with --light-grouping per_light)"};
  }
  return {};
}

Support update_budget_support(const CaseConfig& c) {
  if (c.update_budget_faces == 0) return {};
  if (c.update_budget_faces < 0) return {false, "the update budget must be at least 1 face a frame"};
  if (c.light_grouping == LightGrouping::all_lights)
    return {false, "an update budget with every light in one pass: the pass renders every light's faces"};
  if (c.optimizations.static_cache)
    return {false,
            "an update budget keeps the faces whose light stands still itself (static caching's "
            "saving, face by face): cache adds nothing"};
  if (!refreshes_single_faces(c) && c.update_budget_faces < cube::kFaceCount)
    return {false, "an update budget of " + std::to_string(c.update_budget_faces) +
                       " face(s): " + std::string(to_string(c.technique)) +
                       " refreshes a light's six faces together here (one pass, an atlas block or the "
                       "moments blur), so the budget must be at least 6"};
  return {};
}

}  // namespace

bool refreshes_single_faces(const CaseConfig& c) {
  return traits(c.technique).passes == cube::kFaceCount && c.layout != Layout::atlas &&
         traits(c.layout).geometry.layers == cube::kFaceCount &&
         traits(c.filter).prefilter != Prefilter::separable_blur;
}

Support common_support(const CaseConfig& c) {
  if (traits(c.layout).geometry.map != TexelMap::cube_faces) {
    const std::string name(to_string(c.layout));
    if (c.technique != Technique::six_pass && c.technique != Technique::geometry_shader)
      return {false, name + " is drawn by six_pass (one pass per layer) and geometry_shader so far"};
    if (c.storage != Storage::linear_depth && c.storage != Storage::r32f_distance)
      return {false,
              name +
                  " stores a distance (linear_depth or r32f_distance): its read-back converts no projective "
                  "depth, and its moments filters are not built yet"};
    if (c.optimizations.face_culling)
      return {false, "face culling: the plans cull against cube faces' frusta, not hemispheres"};
    if (c.lookup_perturb_texels != 0.0f) return {false, "--lookup-perturb moves cube lookups only"};
  }
  if (Support s = atlas_support(c); !s.ok) return s;
  if (c.filter == Filter::hw_compare2x2 && c.storage != Storage::linear_depth)
    return {false, "hw_compare2x2 compares against linear distance / far (storage linear_depth); " +
                       std::string(to_string(c.storage)) +
                       (traits(c.storage).checked == DistanceEncoding::colour_distance
                            ? " stores distance in a colour texture"
                        : traits(c.storage).checked == DistanceEncoding::projective_depth
                            ? " stores projective depth"
                            : " is a moments filter's storage (its own filter reads it)")};
  if (!filter_reads(c.filter, c.storage))
    return {false, std::string(to_string(c.filter)) + " reads " +
                       (traits(c.filter).own_storage ? std::string(to_string(*traits(c.filter).own_storage))
                                                     : std::string("a stored distance")) +
                       ", not " + std::string(to_string(c.storage))};
  if (Support s = moments_tuning_support(c.filter, c.moments); !s.ok) return s;
  if (traits(c.filter).prefilter == Prefilter::separable_blur && c.cube_size < 4)
    return {false,
            "the moments blur needs a cube of at least 4 texels a side (a tap folds across one seam only)"};
  if (c.cube_size < 1 || c.width < 1 || c.height < 1)
    return {false, "cube and frame sizes must be at least 1"};
  if (c.light_count < 1) return {false, "the light count must be at least 1"};
  if (Support s = all_lights_support(c); !s.ok) return s;

  if (c.light_count > kLightCubes && c.layout == Layout::cube)
    return {false, std::to_string(c.light_count) +
                       " point lights in layout cube (one cube, one sampler per light): " +
                       std::to_string(kLightCubes) +
                       " at most (a fragment stage samples 16 textures at the least every device allows); "
                       "--layout cube_array holds every light's cube in one texture"};
  if (light_cubes(c) && c.optimizations.light_clusters)
    return {
        false,
        "clustered light lists pick a pixel's lights per pixel, and an array of samplers takes only an index "
        "every invocation shares (dynamically uniform): layout cube with several lights loops over every "
        "light; --layout cube_array takes any index"};
  if (c.technique == Technique::nv_swizzle && c.storage == Storage::hardware_depth)
    return {false,
            "nv_swizzle's clip z is the near plane (a swizzle cannot scale it per face), so the rasteriser's "
            "depth is not the face projection's that hardware_depth stores"};
  if (c.technique == Technique::nv_swizzle && c.raster_perturb_steps != 0.0f)
    return {false, "--raster-perturb moves clip positions before the swizzle could permute them"};
  if (Support s = update_budget_support(c); !s.ok) return s;
  if (c.optimizations.face_culling && traits(c.technique).culling == CullingForm::unsupported)
    return {false,
            "face culling: a multiview pass renders every view of each draw (the view mask is per render "
            "pass), so there is nothing to cull per face"};
  return {};
}

Support layer_count_support(const CaseConfig& c, int max_layers, const std::string& limit) {
  if (c.layout == Layout::atlas) return {};  // one layer: its size is the limit (atlas::too_large)
  const long long layers = static_cast<long long>(traits(c.layout).geometry.layers) * c.light_count;
  if (layers <= max_layers) return {};
  return {false, std::to_string(c.light_count) + " lights of " + std::string(to_string(c.layout)) + " take " +
                     std::to_string(layers) + " layers, above the device's " + std::to_string(max_layers) +
                     " (" + limit + ")"};
}

}  // namespace omnishadow
