#include "backends/common/shader_variants.h"

#include <cmath>
#include <cstdio>
#include <set>

#include "backends/common/case_support.h"
#include "backends/common/layouts.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"
#include "backends/common/view_culling.h"
#include "backends/common/viewport_swizzle.h"

namespace omnishadow::gpu {

std::vector<std::string> shadow_vertex_defines(const CaseConfig& c) {
  const TechniqueTraits& t = traits(c.technique);
  std::vector<std::string> d{std::string(t.vertex_define)};
  // vs_layer's instances follow the draw's face mask: the bounds' faces, or view culling's.
  if (t.culling == CullingForm::per_object_masks &&
      (c.optimizations.face_culling || c.optimizations.view_culling))
    d.push_back("FACE_CULLING");
  if (depth_only(c.storage)) d.push_back("DEPTH_ONLY");
  if (traits(c.layout).geometry.map != TexelMap::cube_faces ||
      (faces_by_viewport(c.layout) && c.technique == Technique::vs_layer))
    d.emplace_back(traits(c.layout).lighting_define);
  if (c.light_grouping == LightGrouping::all_lights) d.push_back("ALL_LIGHTS");
  return d;
}

std::vector<std::string> shadow_geometry_defines(const CaseConfig& c) {
  const TechniqueTraits& t = traits(c.technique);
  if (t.stages == ShadowStages::vertex_passthrough) {
    std::vector<std::string> d{std::string(t.vertex_define)};
    if (c.optimizations.face_culling) d.push_back("FACE_CULLING");
    if (c.optimizations.view_culling && culls_faces_to_view(c)) d.push_back("VIEW_FACES");
    if (depth_only(c.storage)) d.push_back("DEPTH_ONLY");
    if (faces_by_viewport(c.layout))
      d.emplace_back(traits(c.layout).lighting_define);  // the mask alone routes
    if (c.emulate_nv_swizzle) {
      d.push_back("EMULATE_SWIZZLE");
      for (int k = 0; k < 3; ++k)
        d.push_back("SWIZZLES_" + std::to_string(2 * k) + std::to_string(2 * k + 1) + "=" +
                    std::to_string(cube::packed_swizzle_pair(k)) + "u");
    }
    return d;
  }
  if (t.stages != ShadowStages::vertex_geometry) return {};
  std::vector<std::string> d{"TECHNIQUE_GEOMETRY_SHADER"};
  if (t.gs_instanced) d.push_back("GS_INSTANCED");
  if (c.light_grouping == LightGrouping::all_lights) d.push_back("ALL_LIGHTS");
  if (c.optimizations.face_culling) d.push_back("FACE_CULLING");
  if (c.optimizations.view_culling && culls_faces_to_view(c)) d.push_back("VIEW_FACES");
  if (depth_only(c.storage)) d.push_back("DEPTH_ONLY");
  if (const LayoutTraits& layout = traits(c.layout); layout.geometry.map != TexelMap::cube_faces) {
    d.emplace_back(layout.lighting_define);
    d.push_back("LAYOUT_LAYERS=" + std::to_string(layout.geometry.layers));  // the loop over its layers
  }
  if (faces_by_viewport(c.layout)) d.emplace_back(traits(c.layout).lighting_define);  // viewport, not layer
  return d;
}

std::string shadow_geometry_file(const CaseConfig& c) {
  switch (traits(c.technique).stages) {
    case ShadowStages::vertex_geometry:
      return "shadow_depth.geom";
    case ShadowStages::vertex_passthrough:
      return "shadow_swizzle.geom";
    case ShadowStages::vertex:
    case ShadowStages::task_mesh:
      break;
  }
  return "";
}

std::vector<std::string> shadow_mesh_defines(const CaseConfig& c) {
  const TechniqueTraits& t = traits(c.technique);
  if (t.stages != ShadowStages::task_mesh) return {};
  std::vector<std::string> d{std::string(t.vertex_define)};
  if (c.optimizations.face_culling) d.push_back("FACE_CULLING");
  if (depth_only(c.storage)) d.push_back("DEPTH_ONLY");
  if (c.light_grouping == LightGrouping::all_lights) d.push_back("ALL_LIGHTS");
  if (c.emulate_mesh_shader) d.push_back("EMULATE_MESH_SHADER");  // and the fragment stage's input with it
  return d;
}

MeshStageFiles shadow_mesh_files(const CaseConfig& c) {
  if (c.emulate_mesh_shader) return {"shadow_mesh_task.comp", "shadow_mesh_emulation.vert"};
  return {"shadow_mesh.task", "shadow_mesh.mesh"};
}

std::vector<std::string> shadow_fragment_defines(const CaseConfig& c) {
  std::vector<std::string> d{storage_define(c.storage)};
  if (reversed_depth_test(c)) d.push_back("FAR_BY_FRAGMENT");  // nv_swizzle's depth has no far plane
  if (traits(c.layout).geometry.map != TexelMap::cube_faces) d.emplace_back(traits(c.layout).lighting_define);
  if (c.light_grouping == LightGrouping::all_lights) d.push_back("ALL_LIGHTS");
  return d;
}

std::string variant_key(const std::string& file, const std::vector<std::string>& defines) {
  std::string key = file + ":";
  for (size_t i = 0; i < defines.size(); ++i) key += (i ? "," : "") + defines[i];
  return key;
}

std::string storage_define(Storage s) { return std::string(traits(s).define); }

std::string filter_define(Filter f) { return std::string(traits(f).define); }

bool depth_only(Storage s) {
  const StorageTraits& row = traits(s);
  return !row.fragment_depth && row.colour_channels == 0;
}

std::vector<std::string> moments_blur_defines(ColourFormat format) {
  switch (format) {
    case ColourFormat::rg32f:
      return {"MOMENTS_RG32F"};
    case ColourFormat::rg16f:
      return {"MOMENTS_RG16F"};
    case ColourFormat::r32f:
      return {"MOMENTS_R32F"};
    case ColourFormat::r16f:
      return {"MOMENTS_R16F"};
    case ColourFormat::rgba32f:
      return {"MOMENTS_RGBA32F"};
    case ColourFormat::rgba16f:
      return {"MOMENTS_RGBA16F"};
    case ColourFormat::none:
      break;
  }
  return {};
}

std::vector<std::string> lighting_defines(const CaseConfig& c, LightingVariant variant) {
  std::vector<std::string> d{storage_define(c.storage), filter_define(c.filter)};
  if (!traits(c.layout).lighting_define.empty()) d.emplace_back(traits(c.layout).lighting_define);
  if (light_cubes(c)) d.push_back("LIGHT_CUBES");  // a samplerCube per light (layouts.h, kLightCubes)
  if (c.remedies.bias == BiasMode::zero) d.push_back("BIAS_ZERO");
  if (c.remedies.bias == BiasMode::slope) d.push_back("BIAS_SLOPE");
  if (c.remedies.normal_offset) d.push_back("NORMAL_OFFSET");
  if (variant == LightingVariant::check) d.push_back("CHECK_OUTPUTS");
  return d;
}

namespace {
// The optimisations that change a shadow shader: face culling and view culling, each on and off.
std::vector<Optimizations> culling_sets() {
  std::vector<Optimizations> sets;
  for (bool cull : {false, true})
    for (bool view : {false, true}) {
      Optimizations o;
      o.face_culling = cull;
      o.view_culling = view;
      sets.push_back(o);
    }
  return sets;
}

void insert_shadow_keys(std::set<std::string>& keys, const CaseConfig& c) {
  if (traits(c.technique).stages == ShadowStages::task_mesh) {
    const MeshStageFiles files = shadow_mesh_files(c);
    keys.insert(variant_key(files.task, shadow_mesh_defines(c)));
    keys.insert(variant_key(files.mesh, shadow_mesh_defines(c)));
  } else {
    keys.insert(variant_key("shadow_depth.vert", shadow_vertex_defines(c)));
  }
  if (const std::string gs = shadow_geometry_file(c); !gs.empty())
    keys.insert(variant_key(gs, shadow_geometry_defines(c)));
  keys.insert(variant_key("shadow_depth.frag", shadow_fragment_defines(c)));
}
}  // namespace

std::vector<std::string> spirv_variant_keys() {
  std::set<std::string> keys = {
      variant_key("lighting.vert", kNoVariant), variant_key("map_depth.vert", kNoVariant),
      variant_key("map_depth.frag", kNoVariant), variant_key("floor.frag", kNoVariant),
      variant_key("cube_summary.comp", kNoVariant)};
  CaseConfig c;
  for (const TechniqueTraits& t : kTechniques)
    for (Storage storage : all_values<Storage>())
      for (const Optimizations& culling : culling_sets()) {
        c.technique = t.technique;
        c.storage = storage;
        c.optimizations = culling;
        // mesh_shader twice: native, and its test-only emulation (a compute and a vertex shader)
        for (bool emulated : {false, true}) {
          if (emulated && t.technique != Technique::mesh_shader) continue;
          c.emulate_mesh_shader = emulated;
          insert_shadow_keys(keys, c);
          c.light_grouping = LightGrouping::all_lights;  // every light in one pass, where it is built
          for (Filter f : all_values<Filter>()) {        // with a filter that reads the storage
            c.filter = f;
            if (!common_support(c).ok) continue;
            insert_shadow_keys(keys, c);
            break;
          }
          c.filter = Filter::hard;
          c.light_grouping = LightGrouping::per_light;
        }
        c.emulate_mesh_shader = false;
        c.emulate_nv_swizzle =
            t.technique == Technique::nv_swizzle;  // its test-only emulation (an ordinary GS)
        insert_shadow_keys(keys, c);
        c.emulate_nv_swizzle = false;
      }
  // The layouts' own shadow passes where they differ from the cube's (the warp, or faces routed by viewport),
  // for what common_support admits.
  for (const LayoutTraits& layout : kLayouts)
    for (const TechniqueTraits& t : kTechniques)
      for (Storage storage : all_values<Storage>())
        for (const Optimizations& culling : culling_sets()) {
          c = CaseConfig{};
          c.layout = layout.layout;
          c.technique = t.technique;
          c.storage = storage;
          c.optimizations = culling;
          if (layout.geometry.map == TexelMap::cube_faces && !faces_by_viewport(layout.layout)) continue;
          if (!common_support(c).ok) continue;
          insert_shadow_keys(keys, c);
          c.emulate_nv_swizzle = t.technique == Technique::nv_swizzle;  // and its emulation's
          insert_shadow_keys(keys, c);
        }
  c = CaseConfig{};
  for (Storage storage : all_values<Storage>()) {
    if (traits(storage).moments != MomentKind::none)
      for (DepthFormat format : all_values<DepthFormat>())
        keys.insert(variant_key("moments_blur.comp", moments_blur_defines(colour_format(storage, format))));
  }
  for (Storage storage : all_values<Storage>())
    for (Filter filter : all_values<Filter>()) {
      if (!filter_reads(filter, storage)) continue;
      for (const LayoutTraits& layout : kLayouts)
        for (BiasMode bias : {BiasMode::tutorial, BiasMode::zero, BiasMode::slope})
          for (bool normal_offset : {false, true})
            for (LightingVariant v : {LightingVariant::timed, LightingVariant::check}) {
              c.storage = storage;
              c.filter = filter;
              c.layout = layout.layout;
              c.remedies.bias = bias;
              c.remedies.normal_offset = normal_offset;
              const bool own_rules =
                  layout.geometry.map != TexelMap::cube_faces || faces_by_viewport(layout.layout);
              if (own_rules && !common_support(c).ok) continue;
              keys.insert(variant_key("lighting.frag", lighting_defines(c, v)));
              if (layout.layout != Layout::cube) continue;
              c.light_count = 2;  // and with a cube per light
              if (common_support(c).ok) keys.insert(variant_key("lighting.frag", lighting_defines(c, v)));
              c.light_count = 1;
            }
    }
  return {keys.begin(), keys.end()};
}

LightingConstants lighting_constants(const CaseConfig& c, const scene::Scene& s) {
  return {static_cast<int32_t>(s.map_lights.size()), s.has_point_light() ? c.light_count : 0, c.injected_work,
          c.lookup_perturb_texels, c.optimizations.light_clusters ? 1 : 0};
}

namespace {
std::string float_literal(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(v));
  std::string s = buf;
  if (s.find_first_of(".e") == std::string::npos) s += ".0";  // a GLSL float, not an int
  return s;
}
}  // namespace

std::vector<std::string> lighting_constant_defines(const LightingConstants& k) {
  return {"MAP_LIGHTS=" + std::to_string(k.map_lights), "POINT_LIGHTS=" + std::to_string(k.point_lights),
          "INJECTED_WORK=" + std::to_string(k.injected_work),
          "LOOKUP_PERTURB_TEXELS=" + float_literal(k.lookup_perturb_texels),
          "LIGHT_CLUSTERS=" + std::to_string(k.light_clusters)};
}

float raster_perturb_ndc(const CaseConfig& c, int subpixel_bits) {
  // A window offset of k texels is 2k / size in NDC.
  return float(double(c.raster_perturb_steps) * std::ldexp(1.0, -subpixel_bits) * 2.0 / double(c.cube_size));
}

}  // namespace omnishadow::gpu
