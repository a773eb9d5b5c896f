#pragma once
// The render targets of one case: the shadow cube with the views, render pass and framebuffers its technique
// needs, and the lighting targets (lit colour, shadow factor, world position).

#include <vulkan/vulkan.h>

#include <array>
#include <optional>
#include <vector>

#include "backends/common/atlas.h"
#include "backends/common/case_config.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/vulkan/vk_resources.h"

namespace omnishadow::vk {

struct ShadowTargets {
  Storage storage = Storage::linear_depth;
  uint32_t size = 0;    // a layer's edge: the cube's face, or a layout's own (layer_size in layouts.h)
  uint32_t layers = 6;  // 6 cube-compatible layers, or a layout's own (dual_paraboloid: 2, a plain 2D array)
  Image depth;          // the depth test's cube; what the checks read unless r32f_distance
  Image
      color;   // the colour cube beside it: r32f_distance's distances or the moments (GENERAL after the pass)
  Image blur;  // moments filters: the blur's intermediate, six layers a light (GENERAL)
  VkImageView sampled_view = VK_NULL_HANDLE;  // CUBE (CUBE_ARRAY for cube_array, 2D_ARRAY for the other
                                              // layouts) view of what the lighting pass samples (the
                                              // moments for VSM)
  // Layout cube with several lights: light k's six layers of what the lighting pass samples as a CUBE view,
  // one descriptor each (sampled_view is then a 2D_ARRAY view of them all); empty otherwise.
  std::vector<VkImageView> light_cube_views;
  std::vector<VkImageView> attachment_views;  // owned; referenced by the framebuffers
  VkRenderPass render_pass = VK_NULL_HANDLE;  // multiview pass for Technique::multiview
  // six_pass: one per light and face (layer), light-major; otherwise one per light over its layers. Light k's
  // layers are k * layers .. (k + 1) * layers - 1 of every image.
  std::vector<VkFramebuffer> framebuffers;
  // Every light in one pass (LightGrouping::all_lights): one framebuffer over every light's layers; else
  // null.
  VkFramebuffer all_lights_framebuffer = VK_NULL_HANDLE;
  uint32_t lights = 1;
  // Layout atlas: every light's faces are tiles of one layer (backends/common/atlas.h). The render pass then
  // loads (each light's pass clears its own block, so the lights it skips keep their tiles) and starts and
  // ends in the layouts the lighting pass samples; framebuffers[0] covers the whole atlas.
  std::optional<atlas::Plan> atlas;
  const Image& stored() const { return traits(storage).colour_checked ? color : depth; }
};

// The timed variant has the colour and depth only; the check variant adds the shadow factor and world
// position.
struct LightingTargets {
  uint32_t width = 0, height = 0;
  Image color;          // RGBA8
  Image shadow_factor;  // R32F (check variant)
  Image position;       // RGBA32F (check variant)
  Image depth;          // D32F
  std::vector<VkImageView> views;
  VkRenderPass render_pass = VK_NULL_HANDLE;
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
};

// Spot/directional lights: a 2D depth array, one layer and framebuffer per light, sampled as one 2D_ARRAY
// view. `layers` >= 1: a scene without such lights still gets one (1x1) layer, cleared each frame, so the
// lighting pass's sampler always has an image in SHADER_READ_ONLY_OPTIMAL.
struct MapTargets {
  uint32_t size = 0, layers = 0;
  Image depth;
  VkImageView sampled_view = VK_NULL_HANDLE;
  std::vector<VkImageView> layer_views;
  VkRenderPass render_pass = VK_NULL_HANDLE;
  std::vector<VkFramebuffer> framebuffers;
};
MapTargets create_map_targets(VkContext& ctx, uint32_t size, uint32_t layers, DepthFormat format);
void destroy(VkContext& ctx, MapTargets& t);

VkFormat depth_format_of(DepthFormat format);
VkFormat colour_format_of(ColourFormat format);  // VK_FORMAT_UNDEFINED for none
// After the shadow pass the stored cube is in SHADER_READ_ONLY_OPTIMAL; the lighting targets end in
// TRANSFER_SRC_OPTIMAL, ready for read-back.
// `scene`: the loaded scene (layout atlas sizes each light's tiles from it).
ShadowTargets create_shadow_targets(VkContext& ctx, const CaseConfig& config, const scene::Scene& scene);
void destroy(VkContext& ctx, ShadowTargets& t);
LightingTargets create_lighting_targets(VkContext& ctx, uint32_t width, uint32_t height, bool check_outputs);
void destroy(VkContext& ctx, LightingTargets& t);

}  // namespace omnishadow::vk
