#pragma once
// The cube's summary and check grid computed on the GPU (shaders/cube_summary.comp) and read back: 96 bytes
// and the grid instead of the whole cube. Its own descriptor set and compute pipeline, made once per device.

#include <vulkan/vulkan.h>

#include "backends/backend.h"
#include "backends/vulkan/vk_context.h"
#include "backends/vulkan/vk_pipelines.h"
#include "backends/vulkan/vk_resources.h"

namespace omnishadow::vk {

class CubeSummarizer {
 public:
  CubeSummarizer(VkContext& ctx, ShaderModules& modules);
  ~CubeSummarizer();
  CubeSummarizer(const CubeSummarizer&) = delete;
  CubeSummarizer& operator=(const CubeSummarizer&) = delete;

  // `stored`: the cube (6 layers from `first_layer`, SHADER_READ_ONLY_OPTIMAL, left so), last written by a
  // finished submission; `sampler` must not compare. Fills img.cube_summary, img.cube_sample (stored values),
  // img.cube_sample_stride.
  void read(const Image& stored, VkSampler sampler, uint32_t cube_size, Images& img,
            uint32_t first_layer = 0);

 private:
  VkContext& ctx_;
  ComputePipeline compute_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

}  // namespace omnishadow::vk
