#pragma once
// Vulkan side of technique mesh_shader (VK_EXT_mesh_shader): the scene's meshlets in storage buffers
// (backends/common/meshlets.h), built on the scene's first mesh_shader case, their descriptor set and
// pipeline layout (set 0: binding 0 the frame uniforms, 4-8 the meshlet buffers and the scene's vertices, 9
// the light list, 11-12 the emulation's task entries and draws; the object's first task workgroup pushed),
// and the draws; and its test-only emulation (--emulate-mesh-shader): the task stage's compute dispatch and
// the mesh stage's indirect draws.

#include <vulkan/vulkan.h>

#include <array>
#include <vector>

#include "backends/common/meshlets.h"
#include "backends/common/techniques.h"
#include "backends/vulkan/vk_context.h"
#include "backends/vulkan/vk_pipelines.h"
#include "backends/vulkan/vk_resources.h"
#include "scenes/scene.h"

namespace omnishadow::vk {

class VkMeshPass {
 public:
  // scene_vertices must have been created with VK_BUFFER_USAGE_STORAGE_BUFFER_BIT; the buffers outlive this.
  VkMeshPass(VkContext& ctx, const scene::Scene& scene, const gpu::MeshletData& meshlets,
             const Buffer& scene_vertices, const Buffer& frame_uniforms, const Buffer& point_lights);
  ~VkMeshPass();
  VkMeshPass(const VkMeshPass&) = delete;
  VkMeshPass& operator=(const VkMeshPass&) = delete;

  VkPipelineLayout layout() const { return layout_; }
  // pipelines[1] for closed objects (back faces culled), [0] for the rest, as the vertex techniques' draw
  // lists; frame_offset: the dynamic offset of the light's frame uniforms; lights: 1, or every light of the
  // case in one pass (an object's task workgroups are one per task group and light); emulated: the
  // emulation's indirect draws (record_emulated_tasks wrote them) instead of the task launches.
  void draw_list(VkCommandBuffer cb, const std::array<VkPipeline, 2>& pipelines,
                 const std::vector<ObjectDraw>& list, uint64_t& draws, uint32_t frame_offset, uint32_t lights,
                 bool emulated) const;

  // The emulation. create_task_emulation: the task stage's compute pipeline (shaders/shadow_mesh_task.comp,
  // SPIR-V key `key`) in this layout, with buffers for `lights`; record_emulated_tasks, outside a render
  // pass: the dispatch over every task workgroup and the barriers around it. draw_list(emulated) then draws
  // each object's workgroups as indirect draws (one each: multiDrawIndirect is not enabled).
  VkPipeline create_task_emulation(ShaderModules& modules, const std::string& key, uint32_t lights);
  void record_emulated_tasks(VkCommandBuffer cb, VkPipeline task_pipeline, uint32_t frame_offset,
                             uint32_t lights) const;
  // The moving casters' meshlet spheres where the scene's vertices are posed now (the task stage culls by
  // them); the last frame has completed, so the host-visible buffer is free to rewrite.
  void update_spheres(const scene::Scene& posed);

 private:
  void release();
  void write_emulation_descriptors();
  void bind_object(VkCommandBuffer cb, const std::array<VkPipeline, 2>& pipelines, uint32_t object,
                   int& bound, uint32_t frame_offset) const;
  uint32_t task_groups() const { return uint32_t(data_.meshlets.size() / gpu::kMeshletsPerTask); }
  VkContext& ctx_;
  const scene::Scene& scene_;
  gpu::MeshletData data_;
  std::array<Buffer, 4> buffers_{};   // meshlets, spheres (host-visible), vertices, triangles
  std::array<Buffer, 2> emulated_{};  // the emulation's task entries and indirect draws
  uint32_t emulated_tasks_ = 0;       // the task workgroups they hold
  VkShaderStageFlags stages_ = 0;     // every stage of the set and the push range
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  PFN_vkCmdDrawMeshTasksEXT draw_mesh_tasks_ =
      nullptr;  // an extension command: from the device, not the loader
};

}  // namespace omnishadow::vk
