#pragma once
// The macros that select a variant of the shared GLSL (shaders/), one table for both APIs: GL passes them to
// its compiler at run time, Vulkan looks up the SPIR-V that CMakeLists.txt compiled with the same names.

#include <string>
#include <vector>

#include "backends/common/case_config.h"
#include "backends/common/storage_filter_tables.h"
#include "scenes/scene.h"

namespace omnishadow::gpu {

// Shadow pass: the vertex stage's defines (the technique's own; FACE_CULLING for vs_layer with culling;
// ALL_LIGHTS for every light in one pass, also the fragment stage's) and
// the geometry stage's (TECHNIQUE_GEOMETRY_SHADER, GS_INSTANCED for the instanced form, FACE_CULLING); empty
// when the technique has no geometry stage. CMakeLists.txt compiles SPIR-V under exactly these lists.
std::vector<std::string> shadow_vertex_defines(const CaseConfig& c);
std::vector<std::string> shadow_geometry_defines(const CaseConfig& c);
// The geometry stage's file: shadow_depth.geom (layered), shadow_swizzle.geom (nv_swizzle's passthrough), or
// empty.
std::string shadow_geometry_file(const CaseConfig& c);
// mesh_shader's task and mesh stages (shadow_mesh.task, shadow_mesh.mesh): one list for both; empty for the
// other techniques. FACE_CULLING makes the task stage cull meshlets per face; ALL_LIGHTS makes it route every
// light (a task workgroup per meshlet group and light, culled per light and face).
std::vector<std::string> shadow_mesh_defines(const CaseConfig& c);
// The files of mesh_shader's two stages: the native task and mesh stages, or their test-only emulation
// (--emulate-mesh-shader): the task stage as a compute shader, the mesh stage as a vertex shader.
struct MeshStageFiles {
  std::string task, mesh;
};
MeshStageFiles shadow_mesh_files(const CaseConfig& c);
// "shadow_depth.geom:TECHNIQUE_GEOMETRY_SHADER,FACE_CULLING": the key a variant is embedded under.
std::string variant_key(const std::string& file, const std::vector<std::string>& defines);
std::string storage_define(Storage s);
// The shadow pass's fragment stage: the storage's define.
std::vector<std::string> shadow_fragment_defines(const CaseConfig& c);
// shaders/raster_perturb.glsl's constant: CaseConfig::raster_perturb_steps sub-pixel steps of a device with
// `subpixel_bits`, as NDC units of the case's cube face (the 2D maps share its size). 0 unless the test asks.
float raster_perturb_ndc(const CaseConfig& c, int subpixel_bits);
// Stages whose source has no variants are keyed with this one define ("lighting.vert:NONE").
inline const std::vector<std::string> kNoVariant = {"NONE"};
std::string filter_define(Filter f);
// The shadow pass writes no fragment output (hardware_depth): DEPTH_ONLY in its vertex and geometry stages.
bool depth_only(Storage s);
// shaders/moments_blur.comp's format define for a moments cube's format (MOMENTS_RG32F, ...).
std::vector<std::string> moments_blur_defines(ColourFormat format);

// The lighting pass in two variants of one shader (shaders/lighting.frag). `timed` is what a renderer ships
// for the case and the only one the timed frames render: one RGBA8 colour output (+ depth). `check` adds the
// shadow factor (R32F) and world position (RGBA32F) outputs the checks read, and is rendered in the untimed
// check frame only. The colour is computed by the same lines in both, so their lit images must agree bit for
// bit.
enum class LightingVariant { timed, check };
inline constexpr int kLightingColorOutputs[2] = {1, 3};  // by LightingVariant

// The lighting fragment stage: storage, filter, the layout's lookup (LAYOUT_FACE_ARRAY), for the bias
// remedies BIAS_ZERO / BIAS_SLOPE / NORMAL_OFFSET, and CHECK_OUTPUTS for the check variant (CMakeLists.txt
// compiles one SPIR-V per combination).
std::vector<std::string> lighting_defines(const CaseConfig& c, LightingVariant variant);

// What the case's scene has, fixed when the lighting pipeline is built, so the shader holds no loop or branch
// for lights the scene lacks: GL compiles them in as defines, Vulkan passes them as specialisation constants
// with ids 0, 1, 2, 3 (the order of the fields).
struct LightingConstants {
  int32_t map_lights = 0;  // spot and directional lights (0-4), one 2D map each
  int32_t point_lights =
      1;  // point lights shaded, each with its shadow map: the case's light count (0: none)
  int32_t injected_work = 0;  // --inject-fragment-work iterations
  float lookup_perturb_texels =
      0.0f;                    // test only (CaseConfig::lookup_perturb_texels); Vulkan: id 3, as float bits
  int32_t light_clusters = 0;  // 1: each pixel's cluster's lights (--optimize clusters); Vulkan: id 4
};
// Every SPIR-V variant the Vulkan backend can ask for ("lighting.frag:STORAGE_LINEAR_DEPTH,FILTER_HARD",
// ...), enumerated over the tables' axes with the functions above, so the build compiles exactly what the
// backend uses (list_spirv_variants prints it for CMakeLists.txt).
std::vector<std::string> spirv_variant_keys();

LightingConstants lighting_constants(const CaseConfig& c, const scene::Scene& s);
std::vector<std::string> lighting_constant_defines(const LightingConstants& k);  // "MAP_LIGHTS=2", ...

}  // namespace omnishadow::gpu
