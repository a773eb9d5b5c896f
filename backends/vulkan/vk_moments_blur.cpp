#include "backends/vulkan/vk_moments_blur.h"

#include "backends/common/shader_variants.h"

namespace omnishadow::vk {
namespace {

void compute_barrier(VkCommandBuffer cb, VkPipelineStageFlags src_stage, VkAccessFlags src_access,
                     VkPipelineStageFlags dst_stage, VkAccessFlags dst_access) {
  VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cb, src_stage, dst_stage, 0, 1, &b, 0, nullptr, 0, nullptr);
}

}  // namespace

MomentsBlur::MomentsBlur(VkContext& ctx, ShaderModules& modules, ColourFormat format, const Image& moments,
                         const Image& intermediate)
    : ctx_(ctx) {
  VkDevice d = ctx_.device();
  try {
    compute_ = create_compute_pipeline(
        ctx_, modules, gpu::variant_key("moments_blur.comp", gpu::moments_blur_defines(format)),
        {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
        6 * sizeof(int32_t));  // size, axis, first layer, an atlas tile's span, the block's x and y
    allocate_sets(ctx_, {{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 4}}, compute_.set_layout, 2, pool_, sets_);
    views_[0] = create_view(ctx_, moments, VK_IMAGE_VIEW_TYPE_2D_ARRAY, 0, moments.layers);
    views_[1] = create_view(ctx_, intermediate, VK_IMAGE_VIEW_TYPE_2D_ARRAY, 0, intermediate.layers);
    VkDescriptorImageInfo infos[2] = {{VK_NULL_HANDLE, views_[0], VK_IMAGE_LAYOUT_GENERAL},
                                      {VK_NULL_HANDLE, views_[1], VK_IMAGE_LAYOUT_GENERAL}};
    VkWriteDescriptorSet writes[4];
    for (int w = 0; w < 4; ++w) {
      const int axis = w / 2, binding = w % 2;  // axis 0: moments -> intermediate; axis 1: back
      writes[w] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
      writes[w].dstSet = sets_[axis];
      writes[w].dstBinding = uint32_t(binding);
      writes[w].descriptorCount = 1;
      writes[w].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
      writes[w].pImageInfo = &infos[axis == 0 ? binding : 1 - binding];
    }
    vkUpdateDescriptorSets(d, 4, writes, 0, nullptr);
    ctx_.submit_and_wait([&](VkCommandBuffer cb) {
      transition(cb, intermediate, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, 0,
                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
    });
  } catch (...) {
    release();
    throw;
  }
}

MomentsBlur::~MomentsBlur() { release(); }

void MomentsBlur::release() {
  VkDevice d = ctx_.device();
  for (VkImageView& v : views_)
    if (v) vkDestroyImageView(d, v, nullptr), v = VK_NULL_HANDLE;
  if (pool_) vkDestroyDescriptorPool(d, pool_, nullptr), pool_ = VK_NULL_HANDLE;
  destroy(ctx_, compute_);
}

void MomentsBlur::record(VkCommandBuffer cb, uint32_t size, uint32_t first_layer,
                         const atlas::Block* block) const {
  // The shadow pass's render pass made its moments visible to compute reads (its external dependency); the
  // intermediate's last readers and writers were the previous frame's dispatches.
  compute_barrier(
      cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, compute_.pipeline);
  const uint32_t groups = (size + 7) / 8;
  for (int axis = 0; axis < 2; ++axis) {
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, compute_.layout, 0, 1, &sets_[axis], 0,
                            nullptr);
    const int32_t params[6] = {int32_t(size),        axis,
                               int32_t(first_layer), block ? atlas::tile_span(block->face_size) : 0,
                               block ? block->x : 0, block ? block->y : 0};
    vkCmdPushConstants(cb, compute_.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof params, params);
    vkCmdDispatch(cb, groups, groups, 6);
    if (axis == 0)
      compute_barrier(
          cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  }
  compute_barrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                  VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                  VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
}

}  // namespace omnishadow::vk
