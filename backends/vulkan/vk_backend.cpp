#include "backends/vulkan/vk_backend.h"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <chrono>
#include <cstring>
#include <glm/gtc/packing.hpp>

#include "backends/common/cube_faces.h"
#include "backends/common/cube_summary.h"
#include "backends/common/frame_uniforms.h"
#include "backends/common/gpu_layout.h"
#include "backends/common/layouts.h"
#include "backends/common/shader_variants.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"
#include "backends/common/viewport_swizzle.h"

namespace omnishadow::vk {
namespace {

using Clock = std::chrono::steady_clock;

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

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

// The shared table's Vulkan bits, checked against Vulkan's own names; the pool counts exactly those.
constexpr VkQueryPipelineStatisticFlagBits kBits[] = {
    VK_QUERY_PIPELINE_STATISTIC_INPUT_ASSEMBLY_VERTICES_BIT,
    VK_QUERY_PIPELINE_STATISTIC_INPUT_ASSEMBLY_PRIMITIVES_BIT,
    VK_QUERY_PIPELINE_STATISTIC_VERTEX_SHADER_INVOCATIONS_BIT,
    VK_QUERY_PIPELINE_STATISTIC_GEOMETRY_SHADER_INVOCATIONS_BIT,
    VK_QUERY_PIPELINE_STATISTIC_GEOMETRY_SHADER_PRIMITIVES_BIT,
    VK_QUERY_PIPELINE_STATISTIC_CLIPPING_INVOCATIONS_BIT,
    VK_QUERY_PIPELINE_STATISTIC_CLIPPING_PRIMITIVES_BIT,
    VK_QUERY_PIPELINE_STATISTIC_FRAGMENT_SHADER_INVOCATIONS_BIT};
constexpr bool table_matches_vulkan() {
  for (size_t k = 0; k < kPipelineStatistics.size(); ++k)
    if (kPipelineStatistics[k].vk_bit != static_cast<uint32_t>(kBits[k])) return false;
  return std::size(kBits) == kPipelineStatistics.size();
}
static_assert(table_matches_vulkan());
constexpr VkQueryPipelineStatisticFlags statistic_flags() {
  VkQueryPipelineStatisticFlags flags = 0;
  for (const PipelineStatistic& s : kPipelineStatistics) flags |= s.vk_bit;
  return flags;
}
constexpr VkQueryPipelineStatisticFlags kStatistics = statistic_flags();
static_assert(
    VK_VIEWPORT_COORDINATE_SWIZZLE_POSITIVE_X_NV == static_cast<int>(cube::SwizzleComponent::pos_x) &&
        VK_VIEWPORT_COORDINATE_SWIZZLE_NEGATIVE_Y_NV == static_cast<int>(cube::SwizzleComponent::neg_y) &&
        VK_VIEWPORT_COORDINATE_SWIZZLE_NEGATIVE_W_NV == static_cast<int>(cube::SwizzleComponent::neg_w),
    "cube::SwizzleComponent is VkViewportCoordinateSwizzleNV's numbering");

}  // namespace

VkBackend::VkBackend(const std::string& device_selector, bool validation)
    : ctx_(std::make_unique<VkContext>(device_selector, validation)),
      modules_(std::make_unique<ShaderModules>(*ctx_)) {
  describe_device(validation);
  create_layouts();
  create_descriptor_sets();
  create_samplers_and_queries();
  summarizer_ = std::make_unique<CubeSummarizer>(*ctx_, *modules_);
}

void VkBackend::describe_device(bool validation) {
  const VkPhysicalDeviceProperties& p = ctx_->properties();
  info_.api = "Vulkan " + std::to_string(VK_API_VERSION_MAJOR(p.apiVersion)) + "." +
              std::to_string(VK_API_VERSION_MINOR(p.apiVersion)) + "." +
              std::to_string(VK_API_VERSION_PATCH(p.apiVersion));
  char vendor[16];
  std::snprintf(vendor, sizeof vendor, "0x%04x", p.vendorID);
  info_.vendor = vendor;
  info_.renderer = p.deviceName;
  info_.version = std::string(ctx_->driver().driverName) + " " + ctx_->driver().driverInfo;
  info_.platform = "headless (no surface)";
  info_.max_cube_size = static_cast<int>(p.limits.maxImageDimensionCube);
  info_.subpixel_bits = static_cast<int>(p.limits.subPixelPrecisionBits);
  info_.subtexel_bits = static_cast<int>(p.limits.subTexelPrecisionBits);
  info_.shares_host_memory = p.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
  VkPhysicalDeviceMemoryProperties memory{};
  vkGetPhysicalDeviceMemoryProperties(ctx_->physical(), &memory);
  for (uint32_t h = 0; h < memory.memoryHeapCount; ++h)
    if (memory.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      info_.device_memory_bytes = std::max<uint64_t>(info_.device_memory_bytes, memory.memoryHeaps[h].size);
  info_.extra["max_2d_size"] = std::to_string(std::min(
      p.limits.maxImageDimension2D, std::min(p.limits.maxFramebufferWidth, p.limits.maxFramebufferHeight)));
  info_.extra["timestampPeriod_ns"] = std::to_string(p.limits.timestampPeriod);
  info_.extra["timestampValidBits"] = std::to_string(ctx_->timestamp_valid_bits());
  info_.extra["geometryShader"] = ctx_->has_geometry_shader() ? "yes" : "no";
  info_.extra["multiview"] = ctx_->has_multiview() ? "yes" : "no";
  info_.extra["shaderOutputLayer"] = ctx_->has_layer_output() ? "yes" : "no";
  info_.extra["pipelineStatisticsQuery"] = ctx_->has_pipeline_statistics() ? "yes" : "no";
  info_.extra["api_checks"] = validation ? "VK_LAYER_KHRONOS_validation" : "off";
}

void VkBackend::create_layouts() {
  VkDevice d = ctx_->device();
  const VkShaderStageFlags geometry_stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT |
                                             (ctx_->has_geometry_shader() ? VK_SHADER_STAGE_GEOMETRY_BIT : 0);
  // The shadow pass's frame uniforms are per light: a dynamic binding whose offset picks the light's block;
  // with every light in one pass it reads every light's view-projections from the light list.
  VkDescriptorSetLayoutBinding shadow_bindings[2] = {
      {gpu::kFrameUniformsBinding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1, geometry_stages, nullptr},
      {gpu::kPointLightsBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, geometry_stages, nullptr}};
  const VkPhysicalDeviceLimits& limits = ctx_->properties().limits;
  shadow_map_descriptors_ = limits.maxPerStageDescriptorSamplers > uint32_t(kLightCubes) &&
                                    limits.maxDescriptorSetSamplers > uint32_t(kLightCubes)
                                ? uint32_t(kLightCubes)
                                : 1u;
  VkDescriptorSetLayoutBinding bindings[5] = {
      {gpu::kFrameUniformsBinding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, geometry_stages, nullptr},
      {gpu::kShadowMapBinding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, shadow_map_descriptors_,
       VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {gpu::kMapShadowsBinding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT,
       nullptr},
      {gpu::kPointLightsBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {gpu::kLightClustersBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT,
       nullptr}};
  VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  set_info.bindingCount = 2;
  set_info.pBindings = shadow_bindings;
  OMNISHADOW_VK(vkCreateDescriptorSetLayout(d, &set_info, nullptr, &shadow_set_layout_));
  set_info.bindingCount = 5;
  set_info.pBindings = bindings;
  OMNISHADOW_VK(vkCreateDescriptorSetLayout(d, &set_info, nullptr, &lighting_set_layout_));
  // Six 4x4 matrices do not fit the 128 bytes of push constants lavapipe guarantees: they live in the uniform
  // buffer, and only the face index and face mask (gpu::PassUniforms' first 8 bytes) are pushed.
  // The geometry shaders read the face mask too (view culling's faces).
  push_stages_ =
      VK_SHADER_STAGE_VERTEX_BIT | (ctx_->has_geometry_shader() ? VK_SHADER_STAGE_GEOMETRY_BIT : 0);
  VkPushConstantRange push{push_stages_, 0, 2 * sizeof(int32_t)};
  VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &shadow_set_layout_;
  layout_info.pushConstantRangeCount = 1;
  layout_info.pPushConstantRanges = &push;
  OMNISHADOW_VK(vkCreatePipelineLayout(d, &layout_info, nullptr, &shadow_layout_));
  layout_info.pSetLayouts = &lighting_set_layout_;
  layout_info.pushConstantRangeCount = 0;
  OMNISHADOW_VK(vkCreatePipelineLayout(d, &layout_info, nullptr, &lighting_layout_));
}

void VkBackend::create_descriptor_sets() {
  VkDevice d = ctx_->device();
  VkDescriptorPoolSize sizes[4] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1},
                                   {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1},
                                   {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, shadow_map_descriptors_ + 1},
                                   {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3}};
  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.maxSets = 2;
  pool_info.poolSizeCount = 4;
  pool_info.pPoolSizes = sizes;
  OMNISHADOW_VK(vkCreateDescriptorPool(d, &pool_info, nullptr, &descriptor_pool_));
  VkDescriptorSetLayout layouts[2] = {shadow_set_layout_, lighting_set_layout_};
  VkDescriptorSet sets[2];
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = descriptor_pool_;
  alloc.descriptorSetCount = 2;
  alloc.pSetLayouts = layouts;
  OMNISHADOW_VK(vkAllocateDescriptorSets(d, &alloc, sets));
  shadow_set_ = sets[0];
  lighting_set_ = sets[1];

  const VkDeviceSize align = ctx_->properties().limits.minUniformBufferOffsetAlignment;
  frame_stride_ = (sizeof(gpu::FrameUniforms) + align - 1) / align * align;
  frame_uniforms_ =
      create_buffer(*ctx_, frame_stride_ * scene::kMaxPointLights, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true);
  point_lights_ = create_buffer(*ctx_, sizeof(gpu::PointLightRecord) * scene::kMaxPointLights,
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
  VkDescriptorBufferInfo ubo{frame_uniforms_.buffer, 0, sizeof(gpu::FrameUniforms)};
  VkDescriptorBufferInfo lights{point_lights_.buffer, 0, VK_WHOLE_SIZE};
  // [0] shadow: frame uniforms (dynamic), [1] lighting: frame uniforms, [2] lighting and [3] shadow: lights.
  VkWriteDescriptorSet writes[4] = {};
  for (int i = 0; i < 4; ++i) {
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = sets[i == 0 || i == 3 ? 0 : 1];
    writes[i].dstBinding = i >= 2 ? gpu::kPointLightsBinding : gpu::kFrameUniformsBinding;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = i == 0   ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC
                               : i == 1 ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER
                                        : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = i >= 2 ? &lights : &ubo;
  }
  vkUpdateDescriptorSets(d, 4, writes, 0, nullptr);
}

void VkBackend::create_samplers_and_queries() {
  VkDevice d = ctx_->device();
  VkSamplerCreateInfo sampler{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  sampler.magFilter = sampler.minFilter = VK_FILTER_NEAREST;  // the point-shadow tutorial: NEAREST
  sampler.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  sampler.addressModeU = sampler.addressModeV = sampler.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  OMNISHADOW_VK(vkCreateSampler(d, &sampler, nullptr, &nearest_sampler_));
  sampler.magFilter = sampler.minFilter = VK_FILTER_LINEAR;  // hw_compare2x2: 2x2 bilinear compare
  sampler.compareEnable = VK_TRUE;
  sampler.compareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
  OMNISHADOW_VK(vkCreateSampler(d, &sampler, nullptr, &compare_sampler_));
  sampler.compareEnable = VK_FALSE;  // moments: filtered bilinearly, as VSM intends
  OMNISHADOW_VK(vkCreateSampler(d, &sampler, nullptr, &linear_sampler_));

  if (ctx_->timestamp_valid_bits() > 0) {
    VkQueryPoolCreateInfo q{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    q.queryType = VK_QUERY_TYPE_TIMESTAMP;
    q.queryCount = 4;
    OMNISHADOW_VK(vkCreateQueryPool(d, &q, nullptr, &timestamps_));
  }
  if (ctx_->has_pipeline_statistics()) {
    VkQueryPoolCreateInfo q{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    q.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
    q.queryCount = 2;
    q.pipelineStatistics = kStatistics;
    OMNISHADOW_VK(vkCreateQueryPool(d, &q, nullptr, &statistics_));
  }
  VkCommandBufferAllocateInfo cb_alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cb_alloc.commandPool = ctx_->command_pool();
  cb_alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cb_alloc.commandBufferCount = 2;
  OMNISHADOW_VK(vkAllocateCommandBuffers(d, &cb_alloc, command_buffers_.data()));
}

VkBackend::~VkBackend() {
  VkDevice d = ctx_->device();
  vkDeviceWaitIdle(d);
  release_case();
  summarizer_.reset();
  mesh_pass_.reset();
  destroy(*ctx_, vertex_buffer_);
  destroy(*ctx_, moving_staging_);
  destroy(*ctx_, frame_uniforms_);
  destroy(*ctx_, point_lights_);
  vkFreeCommandBuffers(d, ctx_->command_pool(), 2, command_buffers_.data());
  if (timestamps_) vkDestroyQueryPool(d, timestamps_, nullptr);
  if (statistics_) vkDestroyQueryPool(d, statistics_, nullptr);
  vkDestroySampler(d, nearest_sampler_, nullptr);
  vkDestroySampler(d, compare_sampler_, nullptr);
  vkDestroySampler(d, linear_sampler_, nullptr);
  vkDestroyDescriptorPool(d, descriptor_pool_, nullptr);
  vkDestroyPipelineLayout(d, shadow_layout_, nullptr);
  vkDestroyPipelineLayout(d, lighting_layout_, nullptr);
  vkDestroyDescriptorSetLayout(d, shadow_set_layout_, nullptr);
  vkDestroyDescriptorSetLayout(d, lighting_set_layout_, nullptr);
  modules_.reset();
}

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

void VkBackend::upload_scene(const scene::Scene& scene) {
  vkDeviceWaitIdle(ctx_->device());
  release_case();
  mesh_pass_.reset();
  destroy(*ctx_, vertex_buffer_);
  // Also a storage buffer: mesh_shader's mesh stage reads the positions from it (shaders/mesh_common.glsl).
  vertex_buffer_ = upload_buffer(*ctx_, scene.vertices.data(), scene.vertices.size() * sizeof(scene::Vertex),
                                 VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  destroy(*ctx_, moving_staging_);
  moving_regions_.clear();
  moving_pending_ = false;
  VkDeviceSize staged = 0;
  for (const scene::Object& o : scene.objects)
    if (o.moves()) {
      const VkDeviceSize bytes = VkDeviceSize(o.vertex_count) * sizeof(scene::Vertex);
      moving_regions_.push_back({staged, VkDeviceSize(o.first_vertex) * sizeof(scene::Vertex), bytes});
      staged += bytes;
    }
  if (staged) moving_staging_ = create_buffer(*ctx_, staged, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
}

// The previous frame has completed (every submission is waited on), so the staging buffer is free to rewrite.
void VkBackend::upload_moving_objects() {
  auto* staging = static_cast<uint8_t*>(moving_staging_.mapped);
  for (const VkBufferCopy& r : moving_regions_)
    std::memcpy(staging + r.srcOffset, &scene_->vertices[size_t(r.dstOffset / sizeof(scene::Vertex))],
                size_t(r.size));
  moving_pending_ = !moving_regions_.empty();
  // Only for a mesh_shader case (configure_case brings them up to date for the next one). Host-visible: the
  // submission makes them visible.
  if (mesh_pass_ && config_ && traits(config_->technique).stages == ShadowStages::task_mesh)
    mesh_pass_->update_spheres(*scene_);
}

void VkBackend::record_moving_copy(VkCommandBuffer cb) {
  if (!moving_pending_) return;
  vkCmdCopyBuffer(cb, moving_staging_.buffer, vertex_buffer_.buffer, uint32_t(moving_regions_.size()),
                  moving_regions_.data());
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_SHADER_READ_BIT;
  // mesh_shader's mesh stage reads the positions as a storage buffer (shaders/mesh_common.glsl).
  const VkPipelineStageFlags readers =
      VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
      (ctx_->has_mesh_shader() ? VkPipelineStageFlags(VK_PIPELINE_STAGE_MESH_SHADER_BIT_EXT) : 0u);
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, readers, 0, 1, &barrier, 0, nullptr, 0, nullptr);
  moving_pending_ = false;
}

void VkBackend::release_case() {
  VkDevice d = ctx_->device();
  for (VkPipeline p : shadow_pipelines_)
    if (p) vkDestroyPipeline(d, p, nullptr);
  for (auto& variant : lighting_pipelines_)
    for (VkPipeline p : variant)
      if (p) vkDestroyPipeline(d, p, nullptr);
  for (VkPipeline p : floor_pipelines_)
    if (p) vkDestroyPipeline(d, p, nullptr);
  floor_pipelines_ = {};
  for (VkPipeline p : map_pipelines_)
    if (p) vkDestroyPipeline(d, p, nullptr);
  shadow_pipelines_ = {};
  lighting_pipelines_ = {};
  map_pipelines_ = {};
  blur_.reset();
  if (mesh_task_pipeline_) vkDestroyPipeline(d, mesh_task_pipeline_, nullptr);
  mesh_task_pipeline_ = VK_NULL_HANDLE;
  destroy(*ctx_, maps_);
  destroy(*ctx_, shadow_);
  destroy(*ctx_, light_clusters_);
  for (LightingTargets& t : lighting_) destroy(*ctx_, t);
  config_.reset();
}

void VkBackend::configure_case(const CaseConfig& c) {
  vkDeviceWaitIdle(ctx_->device());
  release_case();
  try {
    shadow_ = create_shadow_targets(*ctx_, c, *scene_);
    for (gpu::LightingVariant v : {gpu::LightingVariant::timed, gpu::LightingVariant::check})
      lighting_[size_t(v)] =
          create_lighting_targets(*ctx_, static_cast<uint32_t>(c.width), static_cast<uint32_t>(c.height),
                                  v == gpu::LightingVariant::check);
    // 2D maps share the cube's face size and depth format (one --cube / --depth-format axis sizes both).
    const uint32_t map_layers = static_cast<uint32_t>(scene_->map_lights.size());
    maps_ = create_map_targets(*ctx_, map_layers ? static_cast<uint32_t>(c.cube_size) : 1u,
                               std::max(map_layers, 1u), c.depth_format);
    if (traits(c.technique).stages == ShadowStages::task_mesh) {
      if (!meshlets_) throw std::logic_error("mesh_shader configured on a device without mesh shading");
      if (!mesh_pass_)
        mesh_pass_ = std::make_unique<VkMeshPass>(*ctx_, *scene_, *meshlets_, vertex_buffer_, frame_uniforms_,
                                                  point_lights_);
      // The moving casters where the scene is posed now: other techniques' frames posed it without them.
      mesh_pass_->update_spheres(*scene_);
    }
    if (shadow_draw(c) == ShadowDraw::emulated_mesh_tasks)
      mesh_task_pipeline_ = mesh_pass_->create_task_emulation(
          *modules_, gpu::variant_key(gpu::shadow_mesh_files(c).task, gpu::shadow_mesh_defines(c)),
          mesh_lights(c));
    shadow_draw_ = shadow_draw_step(c);
    create_pipelines(c);
    if (traits(c.filter).prefilter == Prefilter::separable_blur)
      blur_ = std::make_unique<MomentsBlur>(*ctx_, *modules_, colour_format(c.storage, c.depth_format),
                                            shadow_.color, shadow_.blur);
    clusters_ = gpu::LightClusterBuilder(gpu::cluster_grid(scene_->camera, c.width, c.height));
    const size_t cluster_words = c.optimizations.light_clusters
                                     ? gpu::light_cluster_words(clusters_.grid(), c.light_count)
                                     : size_t(gpu::kClusterHeaderWords);
    light_clusters_ =
        create_buffer(*ctx_, cluster_words * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
    write_lighting_descriptors(c);
  } catch (...) {
    release_case();
    throw;
  }
  config_ = c;
  planner_.reset(c.light_count, shadow_.atlas);
}

void VkBackend::create_pipelines(const CaseConfig& c) {
  PipelineDesc map;
  map.stages = {{VK_SHADER_STAGE_VERTEX_BIT, gpu::variant_key("map_depth.vert", gpu::kNoVariant)},
                {VK_SHADER_STAGE_FRAGMENT_BIT, gpu::variant_key("map_depth.frag", gpu::kNoVariant)}};
  map.layout = shadow_layout_;
  map.render_pass = maps_.render_pass;
  map.position_only = true;
  if (c.raster_perturb_steps != 0.0f)
    map.vertex_constants = {std::bit_cast<int32_t>(gpu::raster_perturb_ndc(c, info_.subpixel_bits))};
  const VkCullModeFlags map_culls[3] = {VK_CULL_MODE_NONE, VK_CULL_MODE_BACK_BIT, VK_CULL_MODE_FRONT_BIT};
  for (size_t k = 0; k < 3; ++k) {
    map.cull = map_culls[k];
    map_pipelines_[k] = create_pipeline(*ctx_, *modules_, map);
  }

  PipelineDesc shadow;
  // SPIR-V keys are "<file>:<defines joined by ','>", the names CMakeLists.txt compiled them under.
  const bool mesh = traits(c.technique).stages == ShadowStages::task_mesh;
  if (mesh && c.emulate_mesh_shader) {  // the task stage's compute pipeline: configure_case's
    shadow.stages.push_back({VK_SHADER_STAGE_VERTEX_BIT,
                             gpu::variant_key(gpu::shadow_mesh_files(c).mesh, gpu::shadow_mesh_defines(c))});
  } else if (mesh) {
    shadow.stages.push_back(
        {VK_SHADER_STAGE_TASK_BIT_EXT, gpu::variant_key("shadow_mesh.task", gpu::shadow_mesh_defines(c))});
    shadow.stages.push_back(
        {VK_SHADER_STAGE_MESH_BIT_EXT, gpu::variant_key("shadow_mesh.mesh", gpu::shadow_mesh_defines(c))});
  } else {
    shadow.stages.push_back(
        {VK_SHADER_STAGE_VERTEX_BIT, gpu::variant_key("shadow_depth.vert", gpu::shadow_vertex_defines(c))});
  }
  if (const std::string gs = gpu::shadow_geometry_file(c); !gs.empty())
    shadow.stages.push_back(
        {VK_SHADER_STAGE_GEOMETRY_BIT, gpu::variant_key(gs, gpu::shadow_geometry_defines(c))});
  shadow.stages.push_back(
      {VK_SHADER_STAGE_FRAGMENT_BIT, gpu::variant_key("shadow_depth.frag", gpu::shadow_fragment_defines(c))});
  if (shadow_draw(c) == ShadowDraw::swizzled_viewports)
    for (const cube::FaceSwizzle& f : cube::face_swizzles())
      shadow.viewport_swizzles.push_back(
          {static_cast<VkViewportCoordinateSwizzleNV>(f.x), static_cast<VkViewportCoordinateSwizzleNV>(f.y),
           static_cast<VkViewportCoordinateSwizzleNV>(f.z), static_cast<VkViewportCoordinateSwizzleNV>(f.w)});
  if (reversed_depth_test(c)) shadow.depth_compare = VK_COMPARE_OP_GREATER;
  shadow.viewports = shadow_draw_.viewports;
  shadow.layout = mesh ? mesh_pass_->layout() : shadow_layout_;
  shadow.render_pass = shadow_.render_pass;
  shadow.color_attachments = traits(c.storage).colour_channels > 0 ? 1 : 0;
  shadow.position_only = true;
  // mesh_shader's emulated vertex stage reads the meshlets' buffers, no attribute
  shadow.vertex_input = shadow_draw(c) != ShadowDraw::emulated_mesh_tasks;
  shadow.vertex_constants = map.vertex_constants;
  const gpu::LightingConstants constants = gpu::lighting_constants(c, *scene_);
  for (int cull = 0; cull < 2; ++cull) {
    // two_sided remedy: closed casters keep their back faces in the shadow pass (a light inside one is
    // blocked).
    shadow.cull = cull && !c.remedies.two_sided ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE;
    shadow_pipelines_[static_cast<size_t>(cull)] = create_pipeline(*ctx_, *modules_, shadow);
  }
  for (gpu::LightingVariant v : {gpu::LightingVariant::timed, gpu::LightingVariant::check}) {
    PipelineDesc lighting;
    lighting.stages = {
        {VK_SHADER_STAGE_VERTEX_BIT, gpu::variant_key("lighting.vert", gpu::kNoVariant)},
        {VK_SHADER_STAGE_FRAGMENT_BIT, gpu::variant_key("lighting.frag", gpu::lighting_defines(c, v))}};
    lighting.layout = lighting_layout_;
    lighting.render_pass = lighting_[size_t(v)].render_pass;
    lighting.color_attachments = static_cast<uint32_t>(gpu::kLightingColorOutputs[size_t(v)]);
    lighting.fragment_constants = {constants.map_lights, constants.point_lights, constants.injected_work,
                                   std::bit_cast<int32_t>(constants.lookup_perturb_texels),
                                   constants.light_clusters};
    for (int cull = 0; cull < 2; ++cull) {
      lighting.cull = cull ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE;
      lighting_pipelines_[size_t(v)][static_cast<size_t>(cull)] = create_pipeline(*ctx_, *modules_, lighting);
      if (v != gpu::LightingVariant::timed) continue;
      // The lighting floor: the timed target, lighting.vert with the constant floor.frag (FrameKind::floor).
      PipelineDesc floor = lighting;
      floor.stages[1].second = gpu::variant_key("floor.frag", gpu::kNoVariant);
      floor.fragment_constants.clear();
      floor_pipelines_[static_cast<size_t>(cull)] = create_pipeline(*ctx_, *modules_, floor);
    }
  }
}

void VkBackend::write_lighting_descriptors(const CaseConfig& c) {
  // Written before any command buffer binds the set: lavapipe crashes on a bound, never-written sampler.
  const FilterSampler sampler = traits(c.filter).sampler;
  const VkDescriptorImageInfo image{sampler == FilterSampler::linear_compare   ? compare_sampler_
                                    : sampler == FilterSampler::linear_moments ? linear_sampler_
                                                                               : nearest_sampler_,
                                    shadow_.sampled_view,
                                    traits(c.storage).moments != MomentKind::none
                                        ? VK_IMAGE_LAYOUT_GENERAL
                                        : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  // Every descriptor of binding 2 written (lavapipe crashes on a bound, never-written one): layout cube with
  // several lights, light k's cube in element k and light 0's in those past the last light (never read); any
  // other layout, its one view in element 0 and the same in the rest.
  std::vector<VkDescriptorImageInfo> images(shadow_map_descriptors_, image);
  for (size_t k = 0; k < images.size() && !shadow_.light_cube_views.empty(); ++k)
    images[k].imageView = shadow_.light_cube_views[k < shadow_.light_cube_views.size() ? k : 0];
  VkDescriptorImageInfo map_image{nearest_sampler_, maps_.sampled_view,
                                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  VkDescriptorBufferInfo clusters{light_clusters_.buffer, 0, VK_WHOLE_SIZE};
  VkWriteDescriptorSet writes[3] = {{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                    {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                    {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
  writes[0].dstSet = writes[1].dstSet = lighting_set_;
  writes[0].dstBinding = gpu::kShadowMapBinding;
  writes[1].dstBinding = gpu::kMapShadowsBinding;
  writes[0].descriptorCount = shadow_map_descriptors_;
  writes[1].descriptorCount = 1;
  writes[0].descriptorType = writes[1].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  writes[0].pImageInfo = images.data();
  writes[1].pImageInfo = &map_image;
  writes[2].dstSet = lighting_set_;
  writes[2].dstBinding = gpu::kLightClustersBinding;
  writes[2].descriptorCount = 1;
  writes[2].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  writes[2].pBufferInfo = &clusters;
  vkUpdateDescriptorSets(ctx_->device(), 3, writes, 0, nullptr);
}

// A pass's command buffer opens with its queries: timestamps 2 * pass and 2 * pass + 1 bracket it, and in
// count_work() the pipeline-statistics query `pass` spans it.
void VkBackend::begin_pass(VkCommandBuffer cb, uint32_t pass, bool statistics) {
  OMNISHADOW_VK(vkResetCommandBuffer(cb, 0));
  VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  OMNISHADOW_VK(vkBeginCommandBuffer(cb, &info));
  if (timestamps_) vkCmdResetQueryPool(cb, timestamps_, 2 * pass, 2);
  if (statistics) {
    vkCmdResetQueryPool(cb, statistics_, pass, 1);
    vkCmdBeginQuery(cb, statistics_, pass, 0);
  }
  if (timestamps_) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, timestamps_, 2 * pass);
}

void VkBackend::end_pass(VkCommandBuffer cb, uint32_t pass, bool statistics) {
  if (timestamps_) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps_, 2 * pass + 1);
  if (statistics) vkCmdEndQuery(cb, statistics_, pass);
  OMNISHADOW_VK(vkEndCommandBuffer(cb));
}

// Pipelines [0] for objects drawn two-sided, [1] for closed objects (back faces culled).
void VkBackend::draw_list(VkCommandBuffer cb, const std::array<VkPipeline, 2>& pipelines,
                          VkPipelineLayout layout, VkDescriptorSet set, const std::vector<ObjectDraw>& list,
                          uint64_t& draws) {
  int bound = -1;
  for (const ObjectDraw& d : list) {
    const scene::Object& obj = scene_->objects[d.object];
    if (d.face_mask) {
      const gpu::PassUniforms pass{0, d.face_mask, 0, 0};
      vkCmdPushConstants(cb, layout, push_stages_, 0, 2 * sizeof(int32_t), &pass);
    }
    int want = obj.cull_back_faces ? 1 : 0;
    if (want != bound) {
      vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines[static_cast<size_t>(want)]);
      // The shadow set's uniforms are the light's block being recorded (frame_offset_).
      const bool dynamic = set == shadow_set_;
      if (bound < 0)
        vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &set, dynamic ? 1 : 0,
                                &frame_offset_);
      bound = want;
    }
    vkCmdDraw(cb, obj.vertex_count, d.instances, obj.first_vertex, 0);
    ++draws;
  }
}

void VkBackend::record_maps(VkCommandBuffer cb, uint64_t& draws) {
  VkClearValue clear;
  clear.depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rp.renderPass = maps_.render_pass;
  rp.renderArea = {{0, 0}, {maps_.size, maps_.size}};
  rp.clearValueCount = 1;
  rp.pClearValues = &clear;
  VkViewport viewport{0, 0, float(maps_.size), float(maps_.size), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {maps_.size, maps_.size}};
  VkDeviceSize offset = 0;
  for (uint32_t i = 0; i < maps_.layers; ++i) {
    rp.framebuffer = maps_.framebuffers[i];
    vkCmdBeginRenderPass(cb, &rp, VK_SUBPASS_CONTENTS_INLINE);
    if (i < scene_->map_lights.size()) {  // else the placeholder layer: cleared only
      vkCmdSetViewport(cb, 0, 1, &viewport);
      vkCmdSetScissor(cb, 0, 1, &scissor);
      vkCmdBindVertexBuffers(cb, 0, 1, &vertex_buffer_.buffer, &offset);
      const gpu::PassUniforms pass{static_cast<int32_t>(i), 0, 0, 0};
      vkCmdPushConstants(cb, shadow_layout_, push_stages_, 0, 2 * sizeof(int32_t), &pass);
      // Closed objects: back faces culled as in the cube pass, or front faces (the directional notes'
      // peter-panning fix).
      const size_t closed = scene_->map_lights[i].cull_front_faces ? 2 : 1;
      std::array<VkPipeline, 2> pipelines = {map_pipelines_[0], map_pipelines_[closed]};
      draw_list(cb, pipelines, shadow_layout_, shadow_set_, all_objects_, draws);
    }
    vkCmdEndRenderPass(cb);
  }
}

VkBackend::ShadowDrawStep VkBackend::shadow_draw_step(const CaseConfig& c) {
  // Vertex draws: the vertex buffer, the pass's face in the push constants, each object's draw.
  auto vertex_draws = [this](VkCommandBuffer cb, size_t p, const std::vector<ObjectDraw>& list,
                             uint64_t& draws, bool floor) {
    VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cb, 0, 1, &vertex_buffer_.buffer, &offset);
    const gpu::PassUniforms pass{static_cast<int32_t>(p), 0, 0, 0};
    vkCmdPushConstants(cb, shadow_layout_, push_stages_, 0, 2 * sizeof(int32_t), &pass);
    if (!floor) draw_list(cb, shadow_pipelines_, shadow_layout_, shadow_set_, list, draws);
  };
  switch (shadow_draw(c)) {
    case ShadowDraw::vertex_draws:
      break;
    case ShadowDraw::swizzled_viewports:
      return {cube::kFaceCount, vertex_draws};
    case ShadowDraw::mesh_tasks:  // each object's meshlets (vk_mesh_pass.h), for one light or all of them
      return {1,
              [this, lights = mesh_lights(c)](VkCommandBuffer cb, size_t, const std::vector<ObjectDraw>& list,
                                              uint64_t& draws, bool floor) {
                if (!floor)
                  mesh_pass_->draw_list(cb, shadow_pipelines_, list, draws, frame_offset_, lights, false);
              }};
    case ShadowDraw::emulated_mesh_tasks:  // the same, emulated (record_light_shadow dispatched them)
      return {1,
              [this, lights = mesh_lights(c)](VkCommandBuffer cb, size_t, const std::vector<ObjectDraw>& list,
                                              uint64_t& draws, bool floor) {
                if (!floor)
                  mesh_pass_->draw_list(cb, shadow_pipelines_, list, draws, frame_offset_, lights, true);
              }};
  }
  // Layout atlas: a single pass's faces go to viewports 0-5, one per tile (gl_ViewportIndex).
  return {c.layout == Layout::atlas && traits(c.technique).passes == 1 ? uint32_t(cube::kFaceCount) : 1u,
          vertex_draws};
}

// floor: the case's render passes with their clears and nothing drawn (FrameKind::floor).
void VkBackend::record_shadow(VkCommandBuffer cb, const gpu::LightFrames& frame, bool statistics,
                              uint64_t& draws, bool floor) {
  begin_pass(cb, 0, statistics);
  record_moving_copy(cb);  // the frame's posed casters, before any pass of the frame draws them
  frame_offset_ = 0;
  if (!floor) record_maps(cb, draws);
  // Every light in one pass: its one render pass over every light's layers (the planner renders every light
  // or none).
  const bool all_lights = config_->light_grouping == LightGrouping::all_lights;
  for (uint32_t k = 0; k < (all_lights ? 1u : frame.lights.size()); ++k) {
    // A light whose map holds it already (static caching) or that is out of view is skipped; timestamps and
    // queries still close.
    if (frame.lights[k].skipped() && !floor) continue;
    frame_offset_ = static_cast<uint32_t>(k * frame_stride_);
    record_light_shadow(cb, k, frame.lights[k], draws, floor);
  }
  frame_offset_ = 0;
  // The blurs after every render pass: each binds the moments of every light (one storage view), whose
  // layers must all have left UNDEFINED.
  for (uint32_t k = 0; k < frame.lights.size() && blur_ && !floor; ++k)
    if (!frame.lights[k].skipped()) {
      const atlas::Block* block = shadow_.atlas ? &shadow_.atlas->lights[k] : nullptr;  // its own size
      blur_->record(cb, block ? uint32_t(block->face_size) : shadow_.size, k * shadow_.layers, block);
    }
  end_pass(cb, 0, statistics);
}

// One light's render passes into its layers: six_pass one per face, the others one over the light's layers.
void VkBackend::record_light_shadow(VkCommandBuffer cb, uint32_t light, const gpu::ShadowFrame& frame,
                                    uint64_t& draws, bool floor) {
  VkClearValue clears[2];
  clears[0].color = {{FLT_MAX, FLT_MAX, FLT_MAX, FLT_MAX}};   // r32f: "nothing here" (the multipass tutorial)
  if (traits(shadow_.storage).moments != MomentKind::none) {  // the moments of z = 1, as the depth's clear
    const std::array<float, 4> m = moments_clear_value(shadow_.storage, config_->depth_format,
                                                       config_->moments, frame.uniforms.light_position.w);
    clears[0].color = {{m[0], m[1], m[2], m[3]}};
  }
  clears[1].depthStencil = {reversed_depth_test(*config_) ? 0.0f : 1.0f,
                            0};  // nv_swizzle's r32f: nearer is greater
  const bool colour_first =
      traits(shadow_.storage).colour_channels > 0;  // r32f or moments: a colour attachment
  VkRenderPassBeginInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rp.renderPass = shadow_.render_pass;
  rp.renderArea = {{0, 0}, {shadow_.size, shadow_.size}};
  rp.clearValueCount = colour_first ? 2 : 1;
  rp.pClearValues = colour_first ? clears : clears + 1;
  if (shadow_.atlas) return record_atlas_light(cb, light, frame, rp, draws, floor);
  if (mesh_task_pipeline_ && !floor)  // the emulated task stage, before the render pass its draws are in
    mesh_pass_->record_emulated_tasks(cb, mesh_task_pipeline_, frame_offset_, mesh_lights(*config_));
  VkViewport viewport{0, 0, float(shadow_.size), float(shadow_.size), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {shadow_.size, shadow_.size}};
  const ShadowPassDraws passes = shadow_pass_draws(*config_, frame.plan, scene_->objects.size());
  for (size_t p = 0; p < static_cast<size_t>(passes.count); ++p) {  // six_pass: face p; else the whole cube
    if (passes.count == cube::kFaceCount && !frame.face_pass(int(p)) && !floor) continue;  // view culling
    rp.framebuffer = config_->light_grouping == LightGrouping::all_lights
                         ? shadow_.all_lights_framebuffer
                         : shadow_.framebuffers[light * static_cast<size_t>(passes.count) + p];
    vkCmdBeginRenderPass(cb, &rp, VK_SUBPASS_CONTENTS_INLINE);
    // The viewports alike (nv_swizzle's six, one per face: the pipeline's swizzles tell them apart).
    const std::array<VkViewport, cube::kFaceCount> viewports = {viewport, viewport, viewport,
                                                                viewport, viewport, viewport};
    const std::array<VkRect2D, cube::kFaceCount> scissors = {scissor, scissor, scissor,
                                                             scissor, scissor, scissor};
    vkCmdSetViewport(cb, 0, shadow_draw_.viewports, viewports.data());
    vkCmdSetScissor(cb, 0, shadow_draw_.viewports, scissors.data());
    shadow_draw_.record(cb, p, passes.draws[p], draws, floor);
    vkCmdEndRenderPass(cb);
  }
}

// Layout atlas: one render pass over light k's block (it loads: the other lights' tiles stay), the block
// cleared first, then each pass's faces through their tiles' viewports (six_pass: viewport 0 over face p's
// tile; a single pass: viewports 0-5 over the six, gl_ViewportIndex picks). Scissors are the tiles: no
// fragment leaves its tile.
void VkBackend::record_atlas_light(VkCommandBuffer cb, uint32_t light, const gpu::ShadowFrame& frame,
                                   VkRenderPassBeginInfo rp, uint64_t& draws, bool floor) {
  const atlas::Block& block = shadow_.atlas->lights[light];
  const VkRect2D area{
      {block.x, block.y},
      {uint32_t(atlas::block_width(block.face_size)), uint32_t(atlas::block_height(block.face_size))}};
  // The clear values record_light_shadow chose (colour first where there is one), as attachment clears.
  std::vector<VkClearAttachment> clears;
  for (uint32_t i = 0; i < rp.clearValueCount; ++i) {
    const bool colour = i + 1 < rp.clearValueCount;
    clears.push_back({colour ? VkImageAspectFlags(VK_IMAGE_ASPECT_COLOR_BIT)
                             : VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT),
                      0, rp.pClearValues[i]});
  }
  rp.framebuffer = shadow_.framebuffers[0];
  rp.renderArea = area;
  rp.clearValueCount = 0;
  rp.pClearValues = nullptr;
  vkCmdBeginRenderPass(cb, &rp, VK_SUBPASS_CONTENTS_INLINE);
  const VkClearRect rect{area, 0, 1};
  vkCmdClearAttachments(cb, uint32_t(clears.size()), clears.data(), 1, &rect);
  auto tile = [&](int face, VkViewport& v, VkRect2D& s) {
    const atlas::Texel o = atlas::face_origin(block, face);
    v = {float(o.x), float(o.y), float(block.face_size), float(block.face_size), 0.0f, 1.0f};
    s = {{o.x, o.y}, {uint32_t(block.face_size), uint32_t(block.face_size)}};
  };
  const ShadowPassDraws passes = shadow_pass_draws(*config_, frame.plan, scene_->objects.size());
  for (size_t p = 0; p < static_cast<size_t>(passes.count); ++p) {
    std::array<VkViewport, cube::kFaceCount> viewports{};
    std::array<VkRect2D, cube::kFaceCount> scissors{};
    for (uint32_t f = 0; f < shadow_draw_.viewports; ++f)
      tile(passes.count > 1 ? int(p) : int(f), viewports[f], scissors[f]);
    vkCmdSetViewport(cb, 0, shadow_draw_.viewports, viewports.data());
    vkCmdSetScissor(cb, 0, shadow_draw_.viewports, scissors.data());
    shadow_draw_.record(cb, p, passes.draws[p], draws, floor);
  }
  vkCmdEndRenderPass(cb);
}

void VkBackend::record_lighting(VkCommandBuffer cb, gpu::LightingVariant variant, bool statistics,
                                uint64_t& draws, bool floor) {
  const LightingTargets& target = lighting_[size_t(variant)];
  const uint32_t colors = static_cast<uint32_t>(gpu::kLightingColorOutputs[size_t(variant)]);
  begin_pass(cb, 1, statistics);
  VkClearValue clears[4];
  clears[0].color = {{0.1f, 0.1f, 0.1f, 1.0f}};  // same background as GL
  clears[1].color = {{0, 0, 0, 0}};
  clears[2].color = {{0, 0, 0, 0}};
  clears[colors].depthStencil = {1.0f, 0};  // the depth attachment follows the colour attachments
  VkRenderPassBeginInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rp.renderPass = target.render_pass;
  rp.framebuffer = target.framebuffer;
  rp.renderArea = {{0, 0}, {target.width, target.height}};
  rp.clearValueCount = colors + 1;
  rp.pClearValues = clears;
  vkCmdBeginRenderPass(cb, &rp, VK_SUBPASS_CONTENTS_INLINE);
  VkViewport viewport{0, 0, float(target.width), float(target.height), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {target.width, target.height}};
  vkCmdSetViewport(cb, 0, 1, &viewport);
  vkCmdSetScissor(cb, 0, 1, &scissor);
  VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cb, 0, 1, &vertex_buffer_.buffer, &offset);
  draw_list(cb, floor ? floor_pipelines_ : lighting_pipelines_[size_t(variant)], lighting_layout_,
            lighting_set_, all_objects_, draws);
  vkCmdEndRenderPass(cb);
  end_pass(cb, 1, statistics);
}

double VkBackend::timestamp_ms(uint32_t first) const {
  if (!timestamps_) return -1.0;
  uint64_t ticks[2] = {0, 0};
  OMNISHADOW_VK(vkGetQueryPoolResults(ctx_->device(), timestamps_, first, 2, sizeof ticks, ticks,
                                      sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  const uint32_t bits = ctx_->timestamp_valid_bits();
  const uint64_t mask = bits >= 64 ? ~0ull : ((1ull << bits) - 1);
  const uint64_t delta = ((ticks[1] & mask) - (ticks[0] & mask)) & mask;  // wraps within the valid bits
  return static_cast<double>(delta) * ctx_->properties().limits.timestampPeriod * 1e-6;
}

void VkBackend::write_frame_uniforms(const gpu::LightFrames& frame) {
  auto* base = static_cast<uint8_t*>(frame_uniforms_.mapped);
  for (size_t k = 0; k < frame.lights.size(); ++k)
    std::memcpy(base + k * frame_stride_, &frame.lights[k].uniforms, sizeof(gpu::FrameUniforms));
  std::memcpy(point_lights_.mapped, frame.records.data(),
              frame.records.size() * sizeof(gpu::PointLightRecord));
}

// The frame's clustered light lists, built on the CPU and written for the lighting pass (timed with it).
void VkBackend::write_light_clusters(const gpu::LightFrames& frame) {
  if (!config_->optimizations.light_clusters) return;
  const std::vector<uint32_t>& words = clusters_.build(frame.records);
  std::memcpy(light_clusters_.mapped, words.data(), words.size() * sizeof(uint32_t));
}

FrameTiming VkBackend::render_frame(int frame, FrameKind kind) {
  const auto variant = kind == FrameKind::check ? gpu::LightingVariant::check : gpu::LightingVariant::timed;
  const bool floor = kind == FrameKind::floor;
  // Each pass is its own submission, waited on before the next, so its wall time is its own (as GL's
  // glFinish). cpu_submit covers uniform update, command recording and vkQueueSubmit.
  FrameTiming t;
  uint64_t draws = 0;
  auto t0 = Clock::now();
  gpu::LightFrames plan = planner_.prepare(*scene_, frame, *config_, cube::DepthRange::zero_to_one);
  write_frame_uniforms(plan);
  record_shadow(command_buffers_[0], plan, false, draws, floor);
  ctx_->submit(command_buffers_[0]);
  floor ? planner_.forget() : planner_.rendered(plan, *config_);  // a floor frame leaves the maps cleared
  auto t1 = Clock::now();
  ctx_->wait();
  auto t2 = Clock::now();
  if (!floor) write_light_clusters(plan);  // the floor's lighting reads no light
  record_lighting(command_buffers_[1], variant, false, draws, floor);
  ctx_->submit(command_buffers_[1]);
  auto t3 = Clock::now();
  ctx_->wait();
  auto t4 = Clock::now();
  t.shadow = {ms_between(t0, t1), ms_between(t0, t2), timestamp_ms(0)};
  t.lighting = {ms_between(t2, t3), ms_between(t2, t4), timestamp_ms(2)};
  t.frame_wall_ms = ms_between(t0, t4);
  if (kind == FrameKind::check) {  // the timed variant's colour of the same frame, for the timed_lit check
    record_lighting(command_buffers_[1], gpu::LightingVariant::timed, false, draws);
    ctx_->submit(command_buffers_[1]);
    ctx_->wait();
  }
  return t;
}

FrameCounters VkBackend::count_frame_work(int frame) {
  gpu::LightFrames plan = planner_.prepare(*scene_, frame, *config_, cube::DepthRange::zero_to_one);
  write_frame_uniforms(plan);
  const bool stats = statistics_ != VK_NULL_HANDLE;
  // Mesh draws may not run inside a pipeline-statistics query that counts input-assembly, vertex or geometry
  // work (VK_EXT_mesh_shader's vkCmdDrawMeshTasksEXT), and this pool counts them: mesh_shader's shadow pass
  // is not counted.
  const bool shadow_stats = stats && shadow_draw(*config_) != ShadowDraw::mesh_tasks;
  FrameCounters c;
  record_shadow(command_buffers_[0], plan, shadow_stats, c.shadow.draw_calls);
  ctx_->submit(command_buffers_[0]);
  planner_.rendered(plan, *config_);
  ctx_->wait();
  write_light_clusters(plan);
  record_lighting(command_buffers_[1], gpu::LightingVariant::timed, stats, c.lighting.draw_calls);
  ctx_->submit(command_buffers_[1]);
  ctx_->wait();
  if (stats) {
    PassCounters* passes[2] = {&c.shadow, &c.lighting};
    for (uint32_t p = shadow_stats ? 0 : 1; p < 2; ++p) {
      uint64_t values[kPipelineStatistics.size()] = {};
      OMNISHADOW_VK(vkGetQueryPoolResults(ctx_->device(), statistics_, p, 1, sizeof values, values,
                                          sizeof values, VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
      PassCounters& k = *passes[p];
      k.valid = true;
      for (size_t s = 0; s < kPipelineStatistics.size(); ++s) k.*kPipelineStatistics[s].member = values[s];
    }
  }
  return c;
}

namespace {

// Texels as read back (D16, X8_D24 or 32-bit float: depth or R32F) to floats; UNORM depth to [0, 1].
std::vector<float> decode_texels(VkFormat format, const uint8_t* src, size_t count) {
  std::vector<float> out(count);
  for (size_t i = 0; i < count; ++i) {
    if (format == VK_FORMAT_D16_UNORM) {
      uint16_t x;
      std::memcpy(&x, src + 2 * i, 2);
      out[i] = static_cast<float>(x) / 65535.0f;
    } else if (format == VK_FORMAT_X8_D24_UNORM_PACK32) {
      uint32_t x;
      std::memcpy(&x, src + 4 * i, 4);
      out[i] = static_cast<float>(x & 0xFFFFFFu) / 16777215.0f;
    } else {
      std::memcpy(&out[i], src + 4 * i, 4);
    }
  }
  return out;
}

}  // namespace

// The blurred moments as floats, `moment_channels` a texel (binary16 widened exactly).
void VkBackend::read_moments(Images& img, int light) {
  const int channels = traits(shadow_.storage).colour_channels;
  const bool half = is_half(colour_format(shadow_.storage, config_->depth_format));
  const uint32_t texel_bytes = uint32_t(channels) * (half ? 2u : 4u);
  const std::vector<uint8_t> bytes = read_image(*ctx_, shadow_.color, VK_IMAGE_LAYOUT_GENERAL, texel_bytes);
  const size_t edge = shadow_.atlas ? size_t(shadow_.atlas->lights[size_t(light)].face_size) : shadow_.size;
  const size_t values = edge * edge * size_t(channels);
  img.moment_channels = channels;
  for (size_t f = 0; f < 6; ++f) {
    std::vector<float>& face = img.moments[f];
    face.resize(values);
    const uint8_t* src = bytes.data() + (size_t(light) * shadow_.layers + f) * values * (half ? 2 : 4);
    std::vector<uint8_t> tile;  // layout atlas: the face's rows cut from the layer
    if (shadow_.atlas) {
      const atlas::Block& block = shadow_.atlas->lights[size_t(light)];
      const atlas::Texel o = atlas::face_origin(block, int(f));
      const size_t row = size_t(block.face_size) * texel_bytes;
      tile.resize(row * size_t(block.face_size));
      for (int y = 0; y < block.face_size; ++y)
        std::memcpy(tile.data() + size_t(y) * row,
                    bytes.data() + (size_t(o.y + y) * shadow_.color.width + size_t(o.x)) * texel_bytes, row);
      src = tile.data();
    }
    for (size_t i = 0; i < values; ++i) {
      if (half) {
        uint16_t h;
        std::memcpy(&h, src + 2 * i, 2);
        face[i] = glm::unpackHalf1x16(h);
      } else {
        std::memcpy(&face[i], src + 4 * i, 4);
      }
    }
  }
}

void VkBackend::report_light(int light) {
  const float reported = static_cast<float>(light);  // lights_info.z of light 0's block, which lighting binds
  std::memcpy(static_cast<uint8_t*>(frame_uniforms_.mapped) + offsetof(gpu::FrameUniforms, lights_info) +
                  2 * sizeof(float),
              &reported, sizeof reported);
  uint64_t draws = 0;
  record_lighting(command_buffers_[1], gpu::LightingVariant::check, false, draws);
  ctx_->submit(command_buffers_[1]);
  ctx_->wait();
}

// Layout atlas: the whole layer read back, light k's six tiles cut from it as the faces of a cube (row 0 of a
// tile is t = 0, as a face's).
void VkBackend::read_atlas_faces(Images& img, int light, float near_plane, float far_plane) {
  const Image& stored = shadow_.stored();
  const uint32_t texel_bytes = stored.format == VK_FORMAT_D16_UNORM ? 2 : 4;
  const std::vector<uint8_t> bytes =
      read_image(*ctx_, stored, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, texel_bytes);
  const atlas::Block& block = shadow_.atlas->lights[size_t(light)];
  const int n = block.face_size;
  img.cube_size = n;
  for (int f = 0; f < cube::kFaceCount; ++f) {
    const atlas::Texel o = atlas::face_origin(block, f);
    std::vector<uint8_t> rows(size_t(n) * size_t(n) * texel_bytes);
    for (int y = 0; y < n; ++y)
      std::memcpy(rows.data() + size_t(y) * size_t(n) * texel_bytes,
                  bytes.data() + (size_t(o.y + y) * stored.width + size_t(o.x)) * texel_bytes,
                  size_t(n) * texel_bytes);
    auto& face = img.cube_distance[size_t(f)];
    face = decode_texels(stored.format, rows.data(), size_t(n) * size_t(n));
    for (size_t i = 0; i < face.size(); ++i)
      face[i] = cube::stored_to_distance(shadow_.storage, face[i], int(i % size_t(n)), int(i / size_t(n)), n,
                                         near_plane, far_plane, cube::DepthRange::zero_to_one);
  }
}

Images VkBackend::read_back_images(CubeReadBack cube_read_back, int light) {
  const LightingTargets& check = lighting_[size_t(gpu::LightingVariant::check)];
  Images img;
  img.width = static_cast<int>(check.width);
  img.height = static_cast<int>(check.height);
  const VkImageLayout ready = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  img.lit_rgba8 = read_image(*ctx_, check.color, ready, 4);
  img.timed_lit_rgba8 = read_image(*ctx_, lighting_[size_t(gpu::LightingVariant::timed)].color, ready, 4);
  auto floats = [](const std::vector<uint8_t>& bytes) {
    std::vector<float> out(bytes.size() / sizeof(float));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(float));
    return out;
  };
  img.shadow_factor = floats(read_image(*ctx_, check.shadow_factor, ready, 4));
  img.world_position = floats(read_image(*ctx_, check.position, ready, 16));

  img.cube_size = static_cast<int>(shadow_.size);
  const Image& stored = shadow_.stored();
  // The far the light's map was rendered with (fit_range: per frame).
  const float far_plane = planner_.cube_far(light);
  const float near_plane =
      scene_->has_point_light() ? scene_->point_lights[size_t(light)].near_plane : scene_->light().near_plane;
  img.light_far = far_plane;
  if (cube_read_back == CubeReadBack::sampled && !shadow_.atlas) {
    summarizer_->read(stored, nearest_sampler_, shadow_.size, img, uint32_t(light) * shadow_.layers);
    cube::sample_to_distance(img, shadow_.storage, near_plane, far_plane, cube::DepthRange::zero_to_one);
  }
  const uint32_t texel_bytes = stored.format == VK_FORMAT_D16_UNORM ? 2 : 4;
  std::vector<uint8_t> bytes;
  if (shadow_.atlas) {  // in full: the summary's compute pass reads layers, an atlas's faces are tiles
    read_atlas_faces(img, light, near_plane, far_plane);
    if (blur_) read_moments(img, light);
    cube_read_back = CubeReadBack::sampled;  // nothing more to read
  }
  if (cube_read_back == CubeReadBack::full)
    bytes = read_image(*ctx_, stored, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, texel_bytes);
  const size_t texels = size_t(shadow_.size) * shadow_.size;
  for (size_t f = 0; f < shadow_.layers && !bytes.empty(); ++f) {
    auto& face = img.cube_distance[f];
    const size_t layer = size_t(light) * shadow_.layers + f;
    face = decode_texels(stored.format, bytes.data() + layer * texels * texel_bytes, texels);
    for (size_t i = 0; i < texels; ++i)
      face[i] =
          cube::stored_to_distance(shadow_.storage, face[i], int(i % shadow_.size), int(i / shadow_.size),
                                   int(shadow_.size), near_plane, far_plane, cube::DepthRange::zero_to_one);
  }
  if (blur_ && cube_read_back == CubeReadBack::full) read_moments(img, light);
  if (!scene_->map_lights.empty()) {
    img.map_size = static_cast<int>(maps_.size);
    img.map_depth_zero_to_one = true;
    const uint32_t map_bytes = maps_.depth.format == VK_FORMAT_D16_UNORM ? 2 : 4;
    std::vector<uint8_t> all =
        read_image(*ctx_, maps_.depth, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, map_bytes);
    const size_t map_texels = size_t(maps_.size) * maps_.size;
    for (size_t l = 0; l < scene_->map_lights.size(); ++l)
      img.map_depth.push_back(
          decode_texels(maps_.depth.format, all.data() + l * map_texels * map_bytes, map_texels));
  }
  return img;
}

}  // namespace omnishadow::vk
