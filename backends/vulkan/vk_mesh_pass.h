#pragma once
// Vulkan side of technique mesh_shader (VK_EXT_mesh_shader): the scene's meshlets in storage buffers
// (backends/common/meshlets.h), built on the scene's first mesh_shader case, their descriptor set and
// pipeline layout (set 0: binding 0 the frame uniforms, 4-8 the meshlet buffers and the scene's vertices; the
// object's first task group pushed), and the draws.

#include <vulkan/vulkan.h>

#include <array>
#include <vector>

#include "backends/common/meshlets.h"
#include "backends/common/techniques.h"
#include "backends/vulkan/vk_context.h"
#include "backends/vulkan/vk_resources.h"
#include "scenes/scene.h"

namespace omnishadow::vk {

class VkMeshPass {
 public:
  // scene_vertices must have been created with VK_BUFFER_USAGE_STORAGE_BUFFER_BIT; both buffers outlive this.
  VkMeshPass(VkContext& ctx, const scene::Scene& scene, const gpu::MeshletData& meshlets,
             const Buffer& scene_vertices, const Buffer& frame_uniforms);
  ~VkMeshPass();
  VkMeshPass(const VkMeshPass&) = delete;
  VkMeshPass& operator=(const VkMeshPass&) = delete;

  VkPipelineLayout layout() const { return layout_; }
  // pipelines[1] for closed objects (back faces culled), [0] for the rest, as the vertex techniques' draw
  // lists; frame_offset: the dynamic offset of the light's frame uniforms.
  void draw_list(VkCommandBuffer cb, const std::array<VkPipeline, 2>& pipelines,
                 const std::vector<ObjectDraw>& list, uint64_t& draws, uint32_t frame_offset) const;

 private:
  void release();
  VkContext& ctx_;
  const scene::Scene& scene_;
  gpu::MeshletData data_;
  std::array<Buffer, 4> buffers_{};  // meshlets, spheres, vertices, triangles
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  PFN_vkCmdDrawMeshTasksEXT draw_mesh_tasks_ =
      nullptr;  // an extension command: from the device, not the loader
};

}  // namespace omnishadow::vk
