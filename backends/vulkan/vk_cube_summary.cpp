#include "backends/vulkan/vk_cube_summary.h"

#include "backends/common/cube_summary.h"
#include "backends/common/shader_variants.h"

namespace omnishadow::vk {

CubeSummarizer::CubeSummarizer(VkContext& ctx, ShaderModules& modules) : ctx_(ctx) {
  compute_ =
      create_compute_pipeline(ctx_, modules, gpu::variant_key("cube_summary.comp", gpu::kNoVariant),
                              {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                              2 * sizeof(int32_t));  // size, stride
  allocate_sets(ctx_,
                {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1}, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1}},
                compute_.set_layout, 1, pool_, &set_);
}

CubeSummarizer::~CubeSummarizer() {
  VkDevice d = ctx_.device();
  vkDestroyDescriptorPool(d, pool_, nullptr);
  destroy(ctx_, compute_);
}

void CubeSummarizer::read(const Image& stored, VkSampler sampler, uint32_t cube_size, Images& img,
                          uint32_t first_layer) {
  const size_t bytes = cube::summary_buffer_bytes(int(cube_size));
  Buffer buffer =
      create_buffer(ctx_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
  VkImageView layers = VK_NULL_HANDLE;
  try {
    layers = create_view(ctx_, stored, VK_IMAGE_VIEW_TYPE_2D_ARRAY, first_layer, 6);
    VkDescriptorImageInfo image_info{sampler, layers, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    VkDescriptorBufferInfo buffer_info{buffer.buffer, 0, bytes};
    VkWriteDescriptorSet writes[2] = {{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                      {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
    writes[0].dstSet = writes[1].dstSet = set_;
    writes[0].dstBinding = 0;
    writes[0].descriptorCount = 1;
    writes[0].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    writes[0].pImageInfo = &image_info;
    writes[1].dstBinding = 1;
    writes[1].descriptorCount = 1;
    writes[1].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[1].pBufferInfo = &buffer_info;
    vkUpdateDescriptorSets(ctx_.device(), 2, writes, 0, nullptr);
    const int32_t params[2] = {int32_t(cube_size), int32_t(cube_sample_stride(int(cube_size)))};
    ctx_.submit_and_wait([&](VkCommandBuffer cb) {
      vkCmdFillBuffer(cb, buffer.buffer, 0, VK_WHOLE_SIZE, 0);  // the sums start at 0
      // The fill, and the shadow pass's writes to the cube (an earlier submission), before the shader's
      // accesses.
      VkMemoryBarrier before{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
      before.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                             VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
      before.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
      vkCmdPipelineBarrier(cb,
                           VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                               VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &before, 0, nullptr, 0, nullptr);
      vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, compute_.pipeline);
      vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, compute_.layout, 0, 1, &set_, 0, nullptr);
      vkCmdPushConstants(cb, compute_.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof params, params);
      // 16 x 16 invocations a group, each 16 rows of a column (shaders/cube_summary.comp).
      vkCmdDispatch(cb, (cube_size + 15) / 16, (cube_size + 255) / 256, 6);
      barrier_to_host(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT);
    });
  } catch (...) {
    vkDestroyImageView(ctx_.device(), layers, nullptr);
    destroy(ctx_, buffer);
    throw;
  }
  cube::unpack_summary(buffer.mapped, int(cube_size), img);
  vkDestroyImageView(ctx_.device(), layers, nullptr);
  destroy(ctx_, buffer);
}

}  // namespace omnishadow::vk
