#pragma once
// Shader modules from the embedded SPIR-V, and the graphics pipelines both passes use.

#include <vulkan/vulkan.h>

#include <map>
#include <string>
#include <vector>

#include "backends/vulkan/vk_context.h"

namespace omnishadow::vk {

class ShaderModules {
 public:
  explicit ShaderModules(VkContext& ctx) : ctx_(ctx) {}
  ~ShaderModules();
  // key "shadow_depth.vert:TECHNIQUE_SIX_PASS" (see vk_spirv.h); throws if the variant was not compiled.
  VkShaderModule get(const std::string& key);

 private:
  VkContext& ctx_;
  std::map<std::string, VkShaderModule> modules_;
};

struct PipelineDesc {
  std::vector<std::pair<VkShaderStageFlagBits, std::string>> stages;  // stage, SPIR-V key
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkRenderPass render_pass = VK_NULL_HANDLE;
  uint32_t color_attachments = 0;
  bool position_only = false;  // the shadow pass reads location 0 only
  bool vertex_input = true;    // false: the vertex stage pulls what it reads (mesh_shader's emulation)
  VkCullModeFlags cull = VK_CULL_MODE_NONE;
  // The fragment stage's specialisation constants: value k for constant_id k (4 bytes each; a bool is a
  // VkBool32).
  std::vector<int32_t> fragment_constants;
  // The vertex and geometry stages' (shaders/raster_perturb.glsl: constant_id 0, a float's bits); empty:
  // defaults.
  std::vector<int32_t> vertex_constants;
  // nv_swizzle: one viewport per face with its swizzle (VK_NV_viewport_swizzle); empty: one plain viewport.
  std::vector<VkViewportSwizzleNV> viewport_swizzles;
  uint32_t viewports = 1;  // without swizzles: layout atlas's single pass sets six, one per face's tile
  VkCompareOp depth_compare = VK_COMPARE_OP_LESS;  // GREATER for nv_swizzle's reversed depth (techniques.h)
};

VkPipeline create_pipeline(VkContext& ctx, ShaderModules& modules, const PipelineDesc& desc);

// A compute pipeline with one descriptor set of `bindings` (compute stage) and `push_bytes` of push
// constants.
struct ComputePipeline {
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
};
ComputePipeline create_compute_pipeline(VkContext& ctx, ShaderModules& modules, const std::string& key,
                                        const std::vector<VkDescriptorType>& bindings, uint32_t push_bytes);
void destroy(VkContext& ctx, ComputePipeline& p);  // null handles are skipped

}  // namespace omnishadow::vk
