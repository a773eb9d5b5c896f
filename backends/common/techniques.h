#pragma once
// A technique is one row of one table: how its shadow pass is built and drawn, what a device must have for it, and
// how face culling applies. The matrix, the shader-variant list and both backends read these rows; each backend
// only turns them into API calls. Adding a technique: a Technique value, a row here, its shader variant, and the
// two backends' feature checks.

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
  geometry_shader,   // Vulkan geometryShader (core in GL 4.5)
  layer_from_vertex, // gl_Layer in the vertex stage: GL_ARB_shader_viewport_layer_array / Vulkan shaderOutputLayer
  multiview,         // Vulkan multiview (VK_KHR_multiview, core 1.1) / GL_OVR_multiview2
};

// How --optimize cull reduces the shadow pass's work for the technique.
enum class CullingForm {
  per_face_lists,   // each face's pass draws the objects whose bounds reach it; a face with none is cleared only
  per_triangle_gs,  // the geometry shader skips a triangle for a face it cannot reach; objects reaching no face
                    // are not drawn
  per_object_masks, // one instance per face an object's bounds reach, with the face mask in the draw's uniforms
  unsupported,      // a multiview pass renders every view of each draw (the view mask is per render pass)
};

struct TechniqueTraits {
  Technique technique;
  std::string_view name;           // CLI, case ids, JSON
  std::string_view vertex_define;  // shadow_depth.vert's variant (CMakeLists.txt compiles it)
  bool geometry_stage;             // shadow_depth.geom is in the pipeline
  bool gs_instanced;               // the GS runs 6 invocations, one face each, instead of looping over faces
  int passes;                      // render passes per cube: 6 (one per face) or 1 (layered or multiview)
  uint32_t instances;              // instances per object draw without culling (one per face for vs_layer)
  bool multiview;                  // the render pass carries a 6-view mask; the framebuffer has one layer
  TechniqueFeature feature;
  CullingForm culling;
};

inline constexpr std::array<TechniqueTraits, 5> kTechniques = {{
    {Technique::six_pass, "six_pass", "TECHNIQUE_SIX_PASS", false, false, 6, 1, false, TechniqueFeature::none,
     CullingForm::per_face_lists},
    {Technique::geometry_shader, "geometry_shader", "TECHNIQUE_GEOMETRY_SHADER", true, false, 1, 1, false,
     TechniqueFeature::geometry_shader, CullingForm::per_triangle_gs},
    {Technique::geometry_shader_instanced, "geometry_shader_instanced", "TECHNIQUE_GEOMETRY_SHADER", true, true, 1,
     1, false, TechniqueFeature::geometry_shader, CullingForm::per_triangle_gs},
    {Technique::vs_layer, "vs_layer", "TECHNIQUE_VS_LAYER", false, false, 1, 6, false,
     TechniqueFeature::layer_from_vertex, CullingForm::per_object_masks},
    {Technique::multiview, "multiview", "TECHNIQUE_MULTIVIEW", false, false, 1, 1, true, TechniqueFeature::multiview,
     CullingForm::unsupported},
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

// One object draw of the shadow pass. face_mask != 0: the draw's uniforms carry that mask (per_object_masks), and
// `instances` is its popcount.
struct ObjectDraw {
  uint32_t object;     // index into Scene::objects
  uint32_t instances;
  uint8_t face_mask;
};

// The shadow pass of one frame as both backends issue it: `count` render passes (pass k renders face k when the
// technique has 6, the whole cube otherwise), each with its draws.
struct ShadowPassDraws {
  int count = 0;
  std::array<std::vector<ObjectDraw>, 6> draws;
};
ShadowPassDraws shadow_pass_draws(const CaseConfig& config, const cube::ShadowDrawPlan& plan, size_t object_count);

}  // namespace omnishadow
