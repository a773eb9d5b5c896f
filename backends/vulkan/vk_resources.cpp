#include "backends/vulkan/vk_resources.h"

#include <cstring>

namespace omnishadow::vk {
namespace {

VkDeviceMemory allocate(VkContext& ctx, VkMemoryRequirements req, VkMemoryPropertyFlags props) {
  VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  info.allocationSize = req.size;
  info.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, props);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  OMNISHADOW_VK(vkAllocateMemory(ctx.device(), &info, nullptr, &memory));
  return memory;
}

}  // namespace

Buffer create_buffer(VkContext& ctx, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible) {
  Buffer b;
  b.size = size;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  OMNISHADOW_VK(vkCreateBuffer(ctx.device(), &info, nullptr, &b.buffer));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), b.buffer, &req);
  try {
    b.memory =
        allocate(ctx, req,
                 host_visible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                              : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  } catch (...) {
    destroy(ctx, b);
    throw;
  }
  OMNISHADOW_VK(vkBindBufferMemory(ctx.device(), b.buffer, b.memory, 0));
  if (host_visible) OMNISHADOW_VK(vkMapMemory(ctx.device(), b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped));
  return b;
}

void destroy(VkContext& ctx, Buffer& b) {
  if (b.buffer) vkDestroyBuffer(ctx.device(), b.buffer, nullptr);
  if (b.memory) vkFreeMemory(ctx.device(), b.memory, nullptr);  // unmaps implicitly
  b = Buffer{};
}

void allocate_sets(VkContext& ctx, const std::vector<VkDescriptorPoolSize>& sizes,
                   VkDescriptorSetLayout layout, uint32_t sets, VkDescriptorPool& pool,
                   VkDescriptorSet* out) {
  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.maxSets = sets;
  pool_info.poolSizeCount = static_cast<uint32_t>(sizes.size());
  pool_info.pPoolSizes = sizes.data();
  OMNISHADOW_VK(vkCreateDescriptorPool(ctx.device(), &pool_info, nullptr, &pool));
  const std::vector<VkDescriptorSetLayout> layouts(sets, layout);
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = pool;
  alloc.descriptorSetCount = sets;
  alloc.pSetLayouts = layouts.data();
  OMNISHADOW_VK(vkAllocateDescriptorSets(ctx.device(), &alloc, out));
}

Buffer upload_buffer(VkContext& ctx, const void* data, VkDeviceSize size, VkBufferUsageFlags usage) {
  Buffer staging = create_buffer(ctx, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
  std::memcpy(staging.mapped, data, size);
  Buffer b;
  try {
    b = create_buffer(ctx, size, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);
    ctx.submit_and_wait([&](VkCommandBuffer cb) {
      VkBufferCopy region{0, 0, size};
      vkCmdCopyBuffer(cb, staging.buffer, b.buffer, 1, &region);
    });
  } catch (...) {
    destroy(ctx, staging);
    destroy(ctx, b);
    throw;
  }
  destroy(ctx, staging);
  return b;
}

Image create_image(VkContext& ctx, VkFormat format, uint32_t width, uint32_t height, uint32_t layers,
                   bool cube, VkImageUsageFlags usage) {
  Image i;
  i.format = format;
  i.width = width;
  i.height = height;
  i.layers = layers;
  bool depth = format == VK_FORMAT_D16_UNORM || format == VK_FORMAT_X8_D24_UNORM_PACK32 ||
               format == VK_FORMAT_D32_SFLOAT;
  i.aspect = depth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.flags = cube ? VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT : 0;
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {width, height, 1};
  info.mipLevels = 1;
  info.arrayLayers = layers;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  OMNISHADOW_VK(vkCreateImage(ctx.device(), &info, nullptr, &i.image));
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(ctx.device(), i.image, &req);
  try {
    i.memory = allocate(ctx, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  } catch (...) {
    destroy(ctx, i);
    throw;
  }
  OMNISHADOW_VK(vkBindImageMemory(ctx.device(), i.image, i.memory, 0));
  return i;
}

void destroy(VkContext& ctx, Image& i) {
  if (i.image) vkDestroyImage(ctx.device(), i.image, nullptr);
  if (i.memory) vkFreeMemory(ctx.device(), i.memory, nullptr);
  i = Image{};
}

VkImageView create_view(VkContext& ctx, const Image& image, VkImageViewType type, uint32_t first_layer,
                        uint32_t layer_count) {
  VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  info.image = image.image;
  info.viewType = type;
  info.format = image.format;
  info.subresourceRange = {image.aspect, 0, 1, first_layer, layer_count};
  VkImageView view = VK_NULL_HANDLE;
  OMNISHADOW_VK(vkCreateImageView(ctx.device(), &info, nullptr, &view));
  return view;
}

void transition(VkCommandBuffer cb, const Image& image, VkImageLayout from, VkImageLayout to,
                VkAccessFlags src_access, VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                VkPipelineStageFlags dst_stage) {
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = src_access;
  barrier.dstAccessMask = dst_access;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image.image;
  barrier.subresourceRange = {image.aspect, 0, 1, 0, image.layers};
  vkCmdPipelineBarrier(cb, src_stage, dst_stage, 0, 0, nullptr, 0, nullptr, 1, &barrier);
}

void barrier_to_host(VkCommandBuffer cb, VkPipelineStageFlags stage, VkAccessFlags access) {
  VkMemoryBarrier to_host{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  to_host.srcAccessMask = access;
  to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cb, stage, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0, nullptr, 0, nullptr);
}

std::vector<uint8_t> read_image(VkContext& ctx, const Image& image, VkImageLayout layout,
                                uint32_t texel_bytes) {
  VkDeviceSize size = VkDeviceSize(image.width) * image.height * image.layers * texel_bytes;
  Buffer staging = create_buffer(ctx, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
  try {
    ctx.submit_and_wait([&](VkCommandBuffer cb) {
      VkAccessFlags written =
          VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
      VkPipelineStageFlags producers = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                       VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT |
                                       VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
      if (layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
        transition(cb, image, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, written,
                   VK_ACCESS_TRANSFER_READ_BIT, producers, VK_PIPELINE_STAGE_TRANSFER_BIT);
      VkBufferImageCopy region{};
      region.imageSubresource = {image.aspect, 0, 0, image.layers};
      region.imageExtent = {image.width, image.height, 1};
      vkCmdCopyImageToBuffer(cb, image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.buffer, 1,
                             &region);
      if (layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
        transition(cb, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout, VK_ACCESS_TRANSFER_READ_BIT,
                   VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                   VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
      barrier_to_host(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    });
  } catch (...) {
    destroy(ctx, staging);
    throw;
  }
  std::vector<uint8_t> out(size);
  std::memcpy(out.data(), staging.mapped, size);
  destroy(ctx, staging);
  return out;
}

}  // namespace omnishadow::vk
