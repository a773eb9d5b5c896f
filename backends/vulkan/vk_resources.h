#pragma once
// Buffers and images with their own memory (one allocation each: a benchmark makes a handful per case).

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "backends/vulkan/vk_context.h"

namespace omnishadow::vk {

struct Buffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  void* mapped = nullptr;  // host-visible buffers stay mapped
};

struct Image {
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkImageAspectFlags aspect = 0;
  uint32_t width = 0, height = 0, layers = 1;
};

// host_visible: HOST_VISIBLE | HOST_COHERENT and mapped; otherwise DEVICE_LOCAL.
Buffer create_buffer(VkContext& ctx, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible);
void destroy(VkContext& ctx, Buffer& b);
// A device-local buffer filled from `data` through a staging copy.
Buffer upload_buffer(VkContext& ctx, const void* data, VkDeviceSize size, VkBufferUsageFlags usage);

// A descriptor pool holding exactly `sizes`, and one set of `layout` for each of `sets` allocated from it.
// The pool is returned in `pool` (destroying it frees the sets).
void allocate_sets(VkContext& ctx, const std::vector<VkDescriptorPoolSize>& sizes,
                   VkDescriptorSetLayout layout, uint32_t sets, VkDescriptorPool& pool, VkDescriptorSet* out);

// layers == 6 with cube = true gives a cube-compatible image (six_pass views its layers one by one, layered
// techniques view all six as a 2D array, the lighting pass samples it as a cube).
Image create_image(VkContext& ctx, VkFormat format, uint32_t width, uint32_t height, uint32_t layers,
                   bool cube, VkImageUsageFlags usage);
void destroy(VkContext& ctx, Image& i);
VkImageView create_view(VkContext& ctx, const Image& image, VkImageViewType type, uint32_t first_layer,
                        uint32_t layer_count);

// A layout transition of all layers, as one pipeline barrier.
void transition(VkCommandBuffer cb, const Image& image, VkImageLayout from, VkImageLayout to,
                VkAccessFlags src_access, VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                VkPipelineStageFlags dst_stage);

// Makes writes of `stage` (with `access`) visible to the host once the submission's fence has signalled.
void barrier_to_host(VkCommandBuffer cb, VkPipelineStageFlags stage, VkAccessFlags access);

// Copies every layer of `image` (in `layout`, left there) into host memory, tightly packed, layer after
// layer.
std::vector<uint8_t> read_image(VkContext& ctx, const Image& image, VkImageLayout layout,
                                uint32_t texel_bytes);

}  // namespace omnishadow::vk
