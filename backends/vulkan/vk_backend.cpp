#include "backends/vulkan/vk_backend.h"

#include <algorithm>
#include <cstring>

#include "backends/common/frame_uniforms.h"
#include "backends/common/gpu_layout.h"
#include "backends/common/layouts.h"
#include "backends/common/techniques.h"
#include "backends/common/viewport_swizzle.h"
#include "backends/vulkan/vk_spirv.h"

namespace omnishadow::vk {
namespace {

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
  info_.extra["spirv_optimization"] = embedded_spirv_optimization();
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

}  // namespace omnishadow::vk
