#pragma once
// A technique is one row of one table: how its shadow pass is built and drawn, what a device must have for
// it, and how face culling applies. The matrix, the shader-variant list and both backends read these rows;
// each backend only turns them into API calls. Adding a technique: a Technique value, a row here, its shader
// variant, and the two backends' feature checks; a technique that draws unlike every family so far also a
// ShadowDraw value and its draw step in each backend (GlBackend and VkBackend::shadow_draw_step).

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "backends/common/case_config.h"
#include "backends/common/shadow_plan.h"

namespace omnishadow {

// What a device must expose for the technique (each backend maps it to its extension or feature).
enum class TechniqueFeature {
  none,
  geometry_shader,    // Vulkan geometryShader (core in GL 4.5)
  layer_from_vertex,  // gl_Layer in the vertex stage: GL_ARB_shader_viewport_layer_array / Vulkan
                      // shaderOutputLayer
  multiview,          // Vulkan multiview (VK_KHR_multiview, core 1.1) / GL_OVR_multiview2
  viewport_swizzle,  // VK_NV_viewport_swizzle + VK_NV_viewport_array2 + VK_NV_geometry_shader_passthrough and
                     // multiViewport / the GL_NV_ extensions of the same names
  mesh_shader,       // VK_EXT_mesh_shader (taskShader, meshShader) / GL_NV_mesh_shader
};

// The shadow pass's programmable stages.
enum class ShadowStages {
  vertex,              // shadow_depth.vert, shadow_depth.frag
  vertex_geometry,     // + shadow_depth.geom, layered through gl_Layer
  vertex_passthrough,  // + shadow_swizzle.geom: a passthrough GS that only sets the viewport mask
  task_mesh,  // shadow_mesh.task, shadow_mesh.mesh, shadow_depth.frag: no vertex input; meshlets read from
              // storage buffers (backends/common/meshlets.h)
};

// How a technique family draws its shadow pass. Each backend keeps one draw step per value (its state around
// the pass and its draw per object), chosen when a case is configured; the pass loop they share knows none of
// them.
enum class ShadowDraw {
  vertex_draws,         // one draw per object from the vertex buffer, instanced as the row says
  swizzled_viewports,   // vertex draws into six viewports whose NV swizzles route each to its face
  mesh_tasks,           // task/mesh dispatches over each object's meshlets
  emulated_mesh_tasks,  // --emulate-mesh-shader: a compute dispatch of the task stage, then each object's
                        // task workgroups as indirect draws of the mesh stage's vertex-shader emulation
};

// How --optimize cull reduces the shadow pass's work for the technique.
enum class CullingForm {
  per_face_lists,     // each face's pass draws the objects whose bounds reach it; a face with none is cleared
                      // only
  per_triangle_gs,    // the geometry shader skips a triangle for a face it cannot reach; objects reaching no
                      // face are not drawn
  per_object_masks,   // one instance per face an object's bounds reach, with the face mask in the draw's
                      // uniforms
  unsupported,        // a multiview pass renders every view of each draw (the view mask is per render pass)
  per_triangle_mask,  // the passthrough GS clears a triangle's viewport bit for each face it cannot reach
  per_meshlet_task,   // the task stage sends a meshlet only to the faces its bounding sphere reaches
};

struct TechniqueTraits {
  Technique technique;
  std::string_view name;  // CLI, case ids, JSON
  std::string_view
      vertex_define;  // the shadow pass's variant: shadow_depth.vert's, or the task and mesh stages'
  ShadowStages stages;
  bool gs_instanced;   // the GS runs 6 invocations, one face each, instead of looping over faces
  int passes;          // render passes per cube: 6 (one per face) or 1 (layered or multiview)
  uint32_t instances;  // instances per object draw without culling (one per face for vs_layer)
  bool multiview;      // the render pass carries a 6-view mask; the framebuffer has one layer
  TechniqueFeature feature;
  CullingForm culling;
};

inline constexpr std::array<TechniqueTraits, 7> kTechniques = {{
    {Technique::six_pass, "six_pass", "TECHNIQUE_SIX_PASS", ShadowStages::vertex, false, 6, 1, false,
     TechniqueFeature::none, CullingForm::per_face_lists},
    {Technique::geometry_shader, "geometry_shader", "TECHNIQUE_GEOMETRY_SHADER",
     ShadowStages::vertex_geometry, false, 1, 1, false, TechniqueFeature::geometry_shader,
     CullingForm::per_triangle_gs},
    {Technique::geometry_shader_instanced, "geometry_shader_instanced", "TECHNIQUE_GEOMETRY_SHADER",
     ShadowStages::vertex_geometry, true, 1, 1, false, TechniqueFeature::geometry_shader,
     CullingForm::per_triangle_gs},
    {Technique::vs_layer, "vs_layer", "TECHNIQUE_VS_LAYER", ShadowStages::vertex, false, 1, 6, false,
     TechniqueFeature::layer_from_vertex, CullingForm::per_object_masks},
    {Technique::multiview, "multiview", "TECHNIQUE_MULTIVIEW", ShadowStages::vertex, false, 1, 1, true,
     TechniqueFeature::multiview, CullingForm::unsupported},
    {Technique::nv_swizzle, "nv_swizzle", "TECHNIQUE_NV_SWIZZLE", ShadowStages::vertex_passthrough, false, 1,
     1, false, TechniqueFeature::viewport_swizzle, CullingForm::per_triangle_mask},
    {Technique::mesh_shader, "mesh_shader", "TECHNIQUE_MESH_SHADER", ShadowStages::task_mesh, false, 1, 1,
     false, TechniqueFeature::mesh_shader, CullingForm::per_meshlet_task},
}};

constexpr const TechniqueTraits& traits(Technique t) {
  for (const TechniqueTraits& row : kTechniques)
    if (row.technique == t) return row;
  return kTechniques[0];  // unreachable: every Technique has a row (checked below)
}
constexpr bool every_technique_has_its_row() {
  for (size_t i = 0; i < kTechniques.size(); ++i)
    if (static_cast<size_t>(kTechniques[i].technique) != i) return false;
  return true;
}
static_assert(every_technique_has_its_row(), "kTechniques lists the techniques in enum order");

// nv_swizzle's clip z is the light's near plane and its w the face's axis distance (backends/common/
// viewport_swizzle.h): window depth falls with distance (a reversed, infinite projection). Where the fragment
// stage writes no depth of its own (r32f_distance), the pass tests GREATER against a depth cleared to 0.
bool reversed_depth_test(const CaseConfig& c);
// The configured technique's draw step: from its stages and feature (an emulated nv_swizzle draws vertices:
// its GS applies the swizzles).
ShadowDraw shadow_draw(const CaseConfig& c);
// mesh_shader's lights per draw: its task workgroups are one per task group and light
// (shaders/mesh_common.glsl), so every light in one pass multiplies an object's workgroups by the case's
// lights; 1 per light.
uint32_t mesh_lights(const CaseConfig& c);

// One object draw of the shadow pass. face_mask != 0: the draw's uniforms carry that mask (per_object_masks),
// and `instances` is its popcount.
struct ObjectDraw {
  uint32_t object;  // index into Scene::objects
  uint32_t instances;
  uint8_t face_mask;
};

// The shadow pass of one light as both backends issue it: `count` render passes (pass k renders face k when
// the technique has 6, the whole cube otherwise), each with its draws; with every light in one pass
// (LightGrouping::all_lights) the one pass of every light, each draw instanced for every light's faces.
struct ShadowPassDraws {
  int count = 0;
  std::array<std::vector<ObjectDraw>, 6> draws;
};
ShadowPassDraws shadow_pass_draws(const CaseConfig& config, const cube::ShadowDrawPlan& plan,
                                  size_t object_count);

}  // namespace omnishadow
