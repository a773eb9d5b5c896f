// What the device can run: each refusal names the feature, limit or format and the device.
#include <algorithm>

#include "backends/common/atlas.h"
#include "backends/common/case_support.h"
#include "backends/common/layouts.h"
#include "backends/common/meshlets.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"
#include "backends/vulkan/vk_backend.h"

namespace omnishadow::vk {
namespace {

const char* format_name(VkFormat f) {
  switch (f) {
    case VK_FORMAT_D16_UNORM:
      return "VK_FORMAT_D16_UNORM";
    case VK_FORMAT_X8_D24_UNORM_PACK32:
      return "VK_FORMAT_X8_D24_UNORM_PACK32";
    case VK_FORMAT_D32_SFLOAT:
      return "VK_FORMAT_D32_SFLOAT";
    case VK_FORMAT_R32G32_SFLOAT:
      return "VK_FORMAT_R32G32_SFLOAT";
    case VK_FORMAT_R16G16_SFLOAT:
      return "VK_FORMAT_R16G16_SFLOAT";
    case VK_FORMAT_R32_SFLOAT:
      return "VK_FORMAT_R32_SFLOAT";
    case VK_FORMAT_R16_SFLOAT:
      return "VK_FORMAT_R16_SFLOAT";
    case VK_FORMAT_R32G32B32A32_SFLOAT:
      return "VK_FORMAT_R32G32B32A32_SFLOAT";
    case VK_FORMAT_R16G16B16A16_SFLOAT:
      return "VK_FORMAT_R16G16B16A16_SFLOAT";
    default:
      return "format";
  }
}

}  // namespace

// A moments storage renders its colour cube, blurs it as storage images and samples it bilinearly: its format
// must do all three (linear filtering of 32-bit float formats is optional in Vulkan), and the shader's rg32f,
// rg16f and r16f image formats need shaderStorageImageExtendedFormats (r32f, rgba32f and rgba16f do not).
Support VkBackend::moments_support(const CaseConfig& c, const std::string& device) const {
  if (traits(c.storage).moments == MomentKind::none) return {};
  const ColourFormat colour = colour_format(c.storage, c.depth_format);
  const bool extended =
      colour == ColourFormat::rg32f || colour == ColourFormat::rg16f || colour == ColourFormat::r16f;
  if (extended && !ctx_->has_storage_image_extended_formats())
    return {false, "shaderStorageImageExtendedFormats not supported by " + device + " (the moments blur's " +
                       std::string(to_string(c.storage)) + " format)"};
  const VkFormat format = colour_format_of(colour);
  const VkFormatFeatureFlags needed = VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT |
                                      VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT |
                                      VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
  if ((ctx_->format_properties(format).optimalTilingFeatures & needed) != needed)
    return {false, std::string(format_name(format)) +
                       " cannot be rendered, stored and filtered linearly on " + device + " (" +
                       std::string(to_string(c.filter)) + " needs all three)"};
  return {};
}

// Layout atlas: one 2D texture (and framebuffer and viewport) of every light's tiles; a single pass routes
// faces by viewport.
Support VkBackend::atlas_support(const CaseConfig& c) const {
  if (c.layout != Layout::atlas) return {};
  const std::string device = info_.renderer;
  const VkPhysicalDeviceLimits& limits = ctx_->properties().limits;
  const int max_size =
      int(std::min({limits.maxImageDimension2D, limits.maxFramebufferWidth, limits.maxFramebufferHeight,
                    limits.maxViewportDimensions[0], limits.maxViewportDimensions[1]}));
  if (std::string why =
          atlas::too_large(scene_ ? atlas::plan_for(c, *scene_) : atlas::uniform_plan(c), max_size,
                           "maxImageDimension2D, maxFramebufferWidth/Height, maxViewportDimensions");
      !why.empty())
    return {false, why};
  if (std::string why = atlas::budget_problem(c); !why.empty()) return {false, why};
  if (traits(c.technique).passes == 1 && !ctx_->has_multi_viewport())
    return {false,
            "an atlas's single pass routes faces by viewport: multiViewport not supported by " + device};
  if (c.technique == Technique::vs_layer && !ctx_->has_viewport_output())
    return {false,
            "vs_layer into an atlas writes gl_ViewportIndex in the vertex stage: "
            "shaderOutputViewportIndex (Vulkan 1.2) not supported by " +
                device};
  return {};
}

// mesh_shader's set gives every one of its stages 8 storage buffers: the meshlets' four, the scene's
// vertices, the light list and the emulation's two (vk_mesh_pass.h).
constexpr uint32_t kMeshStorageBuffers = 8;

// mesh_shader natively (VK_EXT_mesh_shader and its set's storage buffers) or emulated, and the scene's task
// workgroups within one launch (native) or one compute dispatch (emulated).
std::string VkBackend::mesh_refusal(const CaseConfig& c) const {
  if (c.emulate_mesh_shader) {
    if (std::string why = mesh_emulation_refusal(); !why.empty()) return why;
  } else if (!ctx_->has_mesh_shader()) {
    return "VK_EXT_mesh_shader (taskShader, meshShader) not supported by " + info_.renderer;
  } else if (std::string why = mesh_storage_refusal(); !why.empty()) {
    return why;
  }
  if (!meshlets_) return {};
  return gpu::mesh_launch_refusal(
      *meshlets_, mesh_lights(c), c.emulate_mesh_shader, ctx_->max_mesh_launch(), "maxTaskWorkGroupCount[0]",
      ctx_->properties().limits.maxComputeWorkGroupCount[0], "maxComputeWorkGroupCount[0]");
}

// The emulated mesh stage is a vertex shader that writes gl_Layer (vs_layer's feature).
std::string VkBackend::mesh_emulation_refusal() const {
  if (!ctx_->has_layer_output())
    return "mesh_shader's emulation writes gl_Layer from the vertex stage: shaderOutputLayer (Vulkan 1.2) is "
           "not supported by " +
           info_.renderer;
  return mesh_storage_refusal();
}

// The set both forms bind (vk_mesh_pass.h) within the device's storage buffers per stage.
std::string VkBackend::mesh_storage_refusal() const {
  const uint32_t buffers = ctx_->properties().limits.maxPerStageDescriptorStorageBuffers;
  if (buffers >= kMeshStorageBuffers) return {};
  return "mesh_shader's stages see " + std::to_string(kMeshStorageBuffers) +
         " storage buffers: maxPerStageDescriptorStorageBuffers " + std::to_string(buffers) + " on " +
         info_.renderer;
}

Support VkBackend::supports(const CaseConfig& c) const {
  if (traits(c.layout).geometry.clips_to_hemisphere && !ctx_->has_clip_distance())
    return {false, std::string(to_string(c.layout)) +
                       " clips each layer's other hemisphere: shaderClipDistance is not supported by " +
                       std::string(ctx_->properties().deviceName)};
  if (Support s = common_support(c); !s.ok) return s;
  const std::string device = info_.renderer;
  switch (traits(c.technique).feature) {
    case TechniqueFeature::geometry_shader:
      if (!ctx_->has_geometry_shader()) return {false, "geometryShader feature not supported by " + device};
      break;
    case TechniqueFeature::layer_from_vertex:
      if (!ctx_->has_layer_output())
        return {false, "shaderOutputLayer (Vulkan 1.2) not supported by " + device};
      break;
    case TechniqueFeature::multiview:
      if (!ctx_->has_multiview()) return {false, "multiview feature not supported by " + device};
      break;
    case TechniqueFeature::viewport_swizzle:
      if (c.emulate_nv_swizzle) {  // an ordinary GS: only geometryShader
        if (!ctx_->has_geometry_shader()) return {false, "geometryShader feature not supported by " + device};
      } else if (!ctx_->missing_for_swizzle().empty())
        return {false, ctx_->missing_for_swizzle() + " not supported by " + device};
      break;
    case TechniqueFeature::mesh_shader:
      if (std::string why = mesh_refusal(c); !why.empty()) return {false, why};
      break;
    case TechniqueFeature::none:
      break;
  }
  if (Support s = atlas_support(c); !s.ok) return s;
  if (light_cubes(c) && shadow_map_descriptors_ < uint32_t(kLightCubes))
    return {false, "layout cube with several lights samples " + std::to_string(kLightCubes + 1) +
                       " textures in the fragment stage (a cube per light and the spot maps): "
                       "maxPerStageDescriptorSamplers " +
                       std::to_string(ctx_->properties().limits.maxPerStageDescriptorSamplers) + " on " +
                       device};
  if (c.layout == Layout::cube_array && !ctx_->has_image_cube_array())
    return {false, "imageCubeArray feature not supported by " + device + " (layout cube_array)"};
  if (Support s = layer_count_support(c, static_cast<int>(ctx_->properties().limits.maxImageArrayLayers),
                                      "maxImageArrayLayers");
      !s.ok)
    return s;
  if (const uint32_t layers = uint32_t(traits(c.layout).geometry.layers * c.light_count);
      c.light_grouping == LightGrouping::all_lights &&
      layers > ctx_->properties().limits.maxFramebufferLayers)
    return {false, "every light in one pass renders " + std::to_string(layers) +
                       " layers, above maxFramebufferLayers " +
                       std::to_string(ctx_->properties().limits.maxFramebufferLayers)};
  if (c.cube_size > info_.max_cube_size)
    return {false, "cube size " + std::to_string(c.cube_size) + " above maxImageDimensionCube " +
                       std::to_string(info_.max_cube_size)};
  if (const int layer = layer_size(c.layout, c.cube_size);
      layer > static_cast<int>(ctx_->properties().limits.maxImageDimension2D))
    return {false, std::string(to_string(c.layout)) + " layers of " + std::to_string(layer) +
                       " texels for cube " + std::to_string(c.cube_size) + " above maxImageDimension2D " +
                       std::to_string(ctx_->properties().limits.maxImageDimension2D)};
  if (Support s = moments_support(c, device); !s.ok) return s;
  VkFormat format = depth_format_of(c.depth_format);
  VkFormatFeatureFlags features = ctx_->format_properties(format).optimalTilingFeatures;
  if (!(features & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT))
    return {false, std::string(format_name(format)) + " cannot be a depth attachment on " + device};
  if (c.storage != Storage::r32f_distance && !(features & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
    return {false, std::string(format_name(format)) + " cannot be sampled on " + device + " (" +
                       std::string(to_string(c.storage)) + " samples it)"};
  if (c.filter == Filter::hw_compare2x2 && !(features & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT))
    return {false, std::string(format_name(format)) + " has no linear filtering on " + device +
                       " (hw_compare2x2 needs it)"};
  return {};
}

}  // namespace omnishadow::vk
