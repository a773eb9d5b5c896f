#pragma once
// C++ mirror of the std140 blocks in shaders/common.glsl, and the vertex layout both backends feed.

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>

#include "scenes/scene.h"

namespace omnishadow::gpu {

struct FrameUniforms {
  glm::mat4 camera_view_proj;
  std::array<glm::mat4, 6> face_view_proj;
  glm::vec4 camera_position;
  glm::vec4 light_position;  // w = light far plane
  glm::vec4 light_color;     // w = light near plane
  glm::vec4 knobs{0.0f};     // x = injected fragment work (iterations), y = PCF radius scale, z = PCSS light
                             // radius, w = the moments filters' parameter (shaders/common.glsl)
  // Spot and directional lights, one 2D map layer each (backends/common/map_lights.h).
  std::array<glm::mat4, 4> map_view_proj{};
  std::array<glm::vec4, 4> map_light{};  // xyz: spot position / directional: unit vector towards the light;
                                         // w: 1 spot, 2 directional
  std::array<glm::vec4, 4> map_color{};  // rgb; w: spot near plane
  std::array<glm::vec4, 4> map_range{};  // x: spot far plane
  glm::vec4 lights_info{0.0f};    // x: number of map lights, y: 1 when the scene has a point light, z: the
                                  // point light whose shadow factor the check variant reports, w: the
                                  // case's point lights (CaseConfig::light_count)
  glm::vec4 moments_knobs{0.0f};  // x: bleed reduction, y: distance scale, z: the format's rounding unit
  // x: how many --cube texels one texel of the pass's target spans, --cube / the target's edge (an atlas
  // tile's N, a paraboloid's or tetrahedron's layer, else 1): --raster-perturb's NDC offset is scaled by it
  // so that every target moves by its own sub-pixel steps (shaders/raster_perturb.glsl). Read only when the
  // perturbation is on.
  glm::vec4 raster_knobs{1.0f, 0.0f, 0.0f, 0.0f};
};
static_assert(sizeof(FrameUniforms) == 11 * 64 + 19 * 16, "std140 layout of FrameUniforms");

// The lighting pass's record of one point light (shaders/common.glsl, std430), the lights in the scene's
// order.
struct PointLightRecord {
  glm::vec4 position_far;   // xyz world units, w the far plane (its range) the light's map was rendered with
  glm::vec4 colour_near;    // rgb, w the near plane
  glm::vec4 moments{0.0f};  // x: the moments filters' distance scale (FrameUniforms::moments_knobs.y)
  // Layout atlas (backends/common/atlas.h): xy the light's block's first texel, z its faces' edge N, w the
  // border, in texels; zero otherwise.
  glm::vec4 atlas_tile{0.0f};
  // The light's layers' view-projections (FrameUniforms::face_view_proj): what the shadow pass reads with
  // every light in one pass (LightGrouping::all_lights).
  std::array<glm::mat4, 6> face_view_proj{};
};
static_assert(sizeof(PointLightRecord) == 64 + 6 * 64, "std430 layout of PointLightRecord");

struct PassUniforms {
  int face;
  uint32_t face_mask;   // vs_layer with face culling: bit f = face f
  uint32_t first_task;  // mesh_shader on Vulkan: the object's first task group (backends/common/meshlets.h)
  int pad;              // std140 rounds a block to 16 bytes
};
inline constexpr int kPassUniformEntries = 64;  // GL: entry k = {face k, mask k}, bound per draw

// Bindings shared by both APIs (shaders/common.glsl, shaders/shadow_filters.glsl).
inline constexpr int kFrameUniformsBinding = 0;
inline constexpr int kPassUniformsBinding = 1;
inline constexpr int kShadowMapBinding = 2;
inline constexpr int kMapShadowsBinding = 3;  // sampler2DArray: one layer per spot/directional light
// Layout cube with several point lights (kLightCubes, layouts.h): one samplerCube per light, an array at
// binding kShadowMapBinding on Vulkan (its descriptorCount) and at units kLightCubesGlUnit.. on GL, clear of
// the others.
inline constexpr int kLightCubesGlUnit = 16;
// mesh_shader's storage buffers (shaders/mesh_common.glsl; GL: shader storage binding points).
inline constexpr int kMeshletsBinding = 4;
inline constexpr int kMeshletSpheresBinding = 5;
inline constexpr int kMeshletVerticesBinding = 6;
inline constexpr int kMeshletTrianglesBinding = 7;
inline constexpr int kSceneVerticesBinding = 8;  // the scene's vertex buffer read as floats
inline constexpr int kPointLightsBinding = 9;    // the lighting pass's PointLightRecord list (storage buffer)
inline constexpr int kLightClustersBinding = 10;  // its per-cluster light lists (gpu::build_light_clusters)
inline constexpr int kFirstMeshBinding = kMeshletsBinding, kMeshBindingCount = 5;
// mesh_shader's test-only emulation (shaders/shadow_mesh_task.comp, shadow_mesh_emulation.vert): the task
// workgroups' entries and their indirect draws (gl_mesh_pass.h, vk_mesh_pass.h).
inline constexpr int kEmulatedTaskEntriesBinding = 11;
inline constexpr int kEmulatedTaskDrawsBinding = 12;

// Vertex attributes: location 0 position, 1 normal, 2 colour; interleaved scene::Vertex.
inline constexpr size_t kVertexStride = sizeof(scene::Vertex);
inline constexpr size_t kPositionOffset = offsetof(scene::Vertex, position);
inline constexpr size_t kNormalOffset = offsetof(scene::Vertex, normal);
inline constexpr size_t kColorOffset = offsetof(scene::Vertex, color);
// shaders/mesh_common.glsl reads positions as floats: 9 a vertex, the position first.
static_assert(kVertexStride == 9 * sizeof(float) && kPositionOffset == 0, "mesh_common.glsl's kVertexFloats");

}  // namespace omnishadow::gpu
