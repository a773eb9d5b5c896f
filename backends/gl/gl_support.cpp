// What the context can run: each refusal names the extension, limit or format and the renderer.
#include "backends/common/atlas.h"
#include "backends/common/case_support.h"
#include "backends/common/gpu_layout.h"
#include "backends/common/layouts.h"
#include "backends/common/meshlets.h"
#include "backends/common/techniques.h"
#include "backends/gl/gl_backend.h"

namespace omnishadow::gl {

Support GlBackend::supports(const CaseConfig& c) const {
  const TechniqueFeature feature = traits(c.technique).feature;
  if (feature == TechniqueFeature::layer_from_vertex && !has_layer_array_)
    return {false, "GL_ARB_shader_viewport_layer_array is not exposed by " + info_.renderer};
  if (Support s = common_support(c); !s.ok) return s;
  if (feature == TechniqueFeature::multiview && !has_multiview_)
    return {false, "GL_OVR_multiview2 with 6 views is not exposed by " + info_.renderer};
  if (feature == TechniqueFeature::viewport_swizzle && !missing_swizzle_.empty() && !c.emulate_nv_swizzle)
    return {false, missing_swizzle_ + " not exposed by " + info_.renderer};
  if (feature == TechniqueFeature::viewport_swizzle && !passthrough_refusal_.empty() && !c.emulate_nv_swizzle)
    return {false, "this " + info_.api +
                       " context links no passthrough geometry shader (GL_NV_viewport_swizzle's "
                       "nv_swizzle needs one; --gl-profile auto tries a compatibility context): " +
                       passthrough_refusal_};
  if (feature == TechniqueFeature::mesh_shader)
    if (std::string why = mesh_refusal(c); !why.empty()) return {false, why};
  if (c.cube_size < 1 || c.cube_size > info_.max_cube_size)
    return {false, "cube size " + std::to_string(c.cube_size) + " outside 1.." +
                       std::to_string(info_.max_cube_size) + " (GL_MAX_CUBE_MAP_TEXTURE_SIZE)"};
  if (Support s = layer_count_support(c, std::stoi(info_.extra.at("max_array_layers")),
                                      "GL_MAX_ARRAY_TEXTURE_LAYERS");
      !s.ok)
    return s;
  if (Support s = all_lights_support(c); !s.ok) return s;
  if (c.optimizations.light_clusters &&
      (max_fragment_storage_blocks_ < 2 || max_storage_bindings_ <= gpu::kLightClustersBinding))
    return {false,
            "clustered light lists are a second storage buffer in the fragment stage at binding " +
                std::to_string(gpu::kLightClustersBinding) + ": GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS " +
                std::to_string(max_fragment_storage_blocks_) + ", GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS " +
                std::to_string(max_storage_bindings_) + " on " + info_.renderer};
  if (light_cubes(c) && (max_fragment_textures_ <= kLightCubes ||
                         max_combined_textures_ < gpu::kLightCubesGlUnit + kLightCubes))
    return {false, "layout cube with several lights samples " + std::to_string(kLightCubes + 1) +
                       " textures in the fragment stage (a cube per light and the spot maps) from unit " +
                       std::to_string(gpu::kLightCubesGlUnit) + ": GL_MAX_TEXTURE_IMAGE_UNITS " +
                       std::to_string(max_fragment_textures_) + ", GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS " +
                       std::to_string(max_combined_textures_) + " on " + info_.renderer};
  if (c.layout == Layout::atlas)
    if (std::string why = atlas::too_large(scene_ ? atlas::plan_for(c, *scene_) : atlas::uniform_plan(c),
                                           std::stoi(info_.extra.at("max_2d_size")), "GL_MAX_TEXTURE_SIZE");
        !why.empty())
      return {false, why};
  if (std::string why = atlas::budget_problem(c); !why.empty()) return {false, why};
  if (const int layer = layer_size(c.layout, c.cube_size); layer > info_.max_cube_size)
    return {false, std::string(to_string(c.layout)) + " layers of " + std::to_string(layer) +
                       " texels for cube " + std::to_string(c.cube_size) + " exceed " +
                       std::to_string(info_.max_cube_size)};
  return {};
}

// mesh_shader natively (GL_NV_mesh_shader) or emulated, and the scene's task workgroups within one launch
// (native) or one compute dispatch (emulated).
std::string GlBackend::mesh_refusal(const CaseConfig& c) const {
  if (!c.emulate_mesh_shader && !has_mesh_shader_)
    return "GL_NV_mesh_shader is not exposed by " + info_.renderer;
  if (c.emulate_mesh_shader)
    if (std::string why = mesh_emulation_refusal(); !why.empty()) return why;
  if (!meshlets_) return {};
  return gpu::mesh_launch_refusal(*meshlets_, mesh_lights(c), c.emulate_mesh_shader,
                                  uint64_t(max_mesh_launch_), "GL_MAX_DRAW_MESH_TASKS_COUNT_NV",
                                  uint64_t(max_compute_groups_), "GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]");
}

// The emulated mesh stage is a vertex shader that writes gl_Layer and reads six storage buffers: the
// meshlets, their vertices and triangles, the scene's vertices, the task entries and the light list.
std::string GlBackend::mesh_emulation_refusal() const {
  if (!has_layer_array_)
    return "mesh_shader's emulation writes gl_Layer from the vertex stage: no "
           "GL_ARB_shader_viewport_layer_array on " +
           info_.renderer;
  if (max_vertex_storage_blocks_ < 6)
    return "mesh_shader's emulation reads 6 storage buffers in the vertex stage: "
           "GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS is " +
           std::to_string(max_vertex_storage_blocks_) + " on " + info_.renderer;
  return {};
}

// Every light in one pass reads the lights' view-projections from a storage buffer in the vertex stage
// (GL 4.5 may expose none there) and renders every light's layers into one layered framebuffer.
Support GlBackend::all_lights_support(const CaseConfig& c) const {
  if (c.light_grouping != LightGrouping::all_lights) return {};
  const bool geometry = c.technique == Technique::geometry_shader;
  if ((geometry ? max_geometry_storage_blocks_ : max_vertex_storage_blocks_) < 1)
    return {false, std::string("every light in one pass reads the lights in the ") +
                       (geometry ? "geometry stage: GL_MAX_GEOMETRY_SHADER_STORAGE_BLOCKS"
                                 : "vertex stage: GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS") +
                       " is 0 on " + info_.renderer};
  if (const int layers = traits(c.layout).geometry.layers * c.light_count; layers > max_framebuffer_layers_)
    return {false, "every light in one pass renders " + std::to_string(layers) + " layers, above " +
                       "GL_MAX_FRAMEBUFFER_LAYERS " + std::to_string(max_framebuffer_layers_)};
  return {};
}

}  // namespace omnishadow::gl
