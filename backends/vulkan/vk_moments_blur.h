#pragma once
// The moments filters' prefilter on Vulkan (shaders/moments_blur.comp): two compute dispatches recorded into
// the shadow pass's command buffer, so their cost is in the timed frame: along s from the moments cube into
// the intermediate, then along t back. Both images stay in GENERAL (storage images; the lighting pass samples
// the moments cube in GENERAL too). One per case: the pipeline is the moments format's variant.

#include <vulkan/vulkan.h>

#include "backends/common/storage_filter_tables.h"
#include "backends/vulkan/vk_context.h"
#include "backends/vulkan/vk_pipelines.h"
#include "backends/vulkan/vk_resources.h"

namespace omnishadow::vk {

class MomentsBlur {
 public:
  // `moments`: the 6-layer moments cube (GENERAL after the shadow pass); `intermediate`: a 6-layer image of
  // its format with STORAGE usage, moved to GENERAL here.
  MomentsBlur(VkContext& ctx, ShaderModules& modules, ColourFormat format, const Image& moments,
              const Image& intermediate);
  ~MomentsBlur();
  MomentsBlur(const MomentsBlur&) = delete;
  MomentsBlur& operator=(const MomentsBlur&) = delete;

  // After the shadow pass's render passes: both passes with their barriers; the blurred moments are then
  // visible to the lighting pass's fragment shader and to transfers (read-back).
  void record(VkCommandBuffer cb, uint32_t size) const;

 private:
  void release();
  VkContext& ctx_;
  ComputePipeline compute_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet sets_[2] = {};  // [axis]: {source, target}
  VkImageView views_[2] = {};     // 2D array views: moments, intermediate
};

}  // namespace omnishadow::vk
