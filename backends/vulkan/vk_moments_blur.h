#pragma once
// The moments filters' prefilter on Vulkan (shaders/moments_blur.comp): two compute dispatches recorded into
// the shadow pass's command buffer, so their cost is in the timed frame: along s from the moments cube into
// the intermediate, then along t back. Both images stay in GENERAL (storage images; the lighting pass samples
// the moments cube in GENERAL too). One per case: the pipeline is the moments format's variant.

#include <vulkan/vulkan.h>

#include "backends/common/atlas.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/vulkan/vk_context.h"
#include "backends/vulkan/vk_pipelines.h"
#include "backends/vulkan/vk_resources.h"

namespace omnishadow::vk {

class MomentsBlur {
 public:
  // `moments`: the moments cubes, six layers a light (GENERAL after the shadow pass); `intermediate`: an
  // image of its format and layers with STORAGE usage, moved to GENERAL here.
  MomentsBlur(VkContext& ctx, ShaderModules& modules, ColourFormat format, const Image& moments,
              const Image& intermediate);
  ~MomentsBlur();
  MomentsBlur(const MomentsBlur&) = delete;
  MomentsBlur& operator=(const MomentsBlur&) = delete;

  // After a light's shadow render passes: both passes over its cube (layers first_layer..+5) with their
  // barriers; the blurred moments are then visible to the lighting pass's fragment shader and to transfers.
  // Layout atlas: `block` is the light's (its faces are tiles of layer 0; first_layer unused).
  void record(VkCommandBuffer cb, uint32_t size, uint32_t first_layer,
              const atlas::Block* block = nullptr) const;

 private:
  void release();
  VkContext& ctx_;
  ComputePipeline compute_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet sets_[2] = {};  // [axis]: {source, target}
  VkImageView views_[2] = {};     // 2D array views: moments, intermediate
};

}  // namespace omnishadow::vk
