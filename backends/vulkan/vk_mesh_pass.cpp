#include "backends/vulkan/vk_mesh_pass.h"

#include <stdexcept>

#include "backends/common/gpu_layout.h"

namespace omnishadow::vk {
namespace {

template <typename T>
Buffer storage_buffer(VkContext& ctx, const std::vector<T>& data) {
  static const T zero{};  // a zero-sized buffer is invalid: an empty scene still binds one element
  return data.empty()
             ? upload_buffer(ctx, &zero, sizeof(T), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT)
             : upload_buffer(ctx, data.data(), data.size() * sizeof(T), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
}

}  // namespace

VkMeshPass::VkMeshPass(VkContext& ctx, const scene::Scene& scene, const gpu::MeshletData& meshlets,
                       const Buffer& scene_vertices, const Buffer& frame_uniforms)
    : ctx_(ctx), scene_(scene), data_(meshlets) {
  VkDevice d = ctx_.device();
  try {
    draw_mesh_tasks_ =
        reinterpret_cast<PFN_vkCmdDrawMeshTasksEXT>(vkGetDeviceProcAddr(d, "vkCmdDrawMeshTasksEXT"));
    if (!draw_mesh_tasks_) throw std::runtime_error("vkCmdDrawMeshTasksEXT is not available on this device");
    buffers_ = {storage_buffer(ctx_, data_.meshlets), storage_buffer(ctx_, data_.spheres),
                storage_buffer(ctx_, data_.vertices), storage_buffer(ctx_, data_.triangles)};

    const VkShaderStageFlags mesh_stages = VK_SHADER_STAGE_TASK_BIT_EXT | VK_SHADER_STAGE_MESH_BIT_EXT;
    std::vector<VkDescriptorSetLayoutBinding> bindings = {
        {gpu::kFrameUniformsBinding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1,
         mesh_stages | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
    for (int b = 0; b < gpu::kMeshBindingCount; ++b)
      bindings.push_back({static_cast<uint32_t>(gpu::kFirstMeshBinding + b),
                          VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, mesh_stages, nullptr});
    VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    set_info.bindingCount = static_cast<uint32_t>(bindings.size());
    set_info.pBindings = bindings.data();
    OMNISHADOW_VK(vkCreateDescriptorSetLayout(d, &set_info, nullptr, &set_layout_));
    // face, face_mask, first_task: shaders/common.glsl's push block with TECHNIQUE_MESH_SHADER.
    VkPushConstantRange push{mesh_stages, 0, 3 * sizeof(uint32_t)};
    VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout_;
    layout_info.pushConstantRangeCount = 1;
    layout_info.pPushConstantRanges = &push;
    OMNISHADOW_VK(vkCreatePipelineLayout(d, &layout_info, nullptr, &layout_));

    allocate_sets(ctx_,
                  {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1},
                   {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, static_cast<uint32_t>(gpu::kMeshBindingCount)}},
                  set_layout_, 1, pool_, &set_);

    std::vector<VkDescriptorBufferInfo> infos = {{frame_uniforms.buffer, 0, sizeof(gpu::FrameUniforms)}};
    for (const Buffer& b : buffers_) infos.push_back({b.buffer, 0, VK_WHOLE_SIZE});
    infos.push_back({scene_vertices.buffer, 0, VK_WHOLE_SIZE});
    std::vector<VkWriteDescriptorSet> writes(infos.size(), {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET});
    for (size_t i = 0; i < infos.size(); ++i) {
      writes[i].dstSet = set_;
      writes[i].dstBinding = bindings[i].binding;
      writes[i].descriptorCount = 1;
      writes[i].descriptorType = bindings[i].descriptorType;
      writes[i].pBufferInfo = &infos[i];
    }
    vkUpdateDescriptorSets(d, static_cast<uint32_t>(writes.size()), writes.data(), 0, nullptr);
  } catch (...) {
    release();
    throw;
  }
}

VkMeshPass::~VkMeshPass() { release(); }

void VkMeshPass::release() {
  VkDevice d = ctx_.device();
  if (pool_) vkDestroyDescriptorPool(d, pool_, nullptr);
  if (layout_) vkDestroyPipelineLayout(d, layout_, nullptr);
  if (set_layout_) vkDestroyDescriptorSetLayout(d, set_layout_, nullptr);
  pool_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
  set_layout_ = VK_NULL_HANDLE;
  for (Buffer& b : buffers_) destroy(ctx_, b);
}

void VkMeshPass::draw_list(VkCommandBuffer cb, const std::array<VkPipeline, 2>& pipelines,
                           const std::vector<ObjectDraw>& list, uint64_t& draws,
                           uint32_t frame_offset) const {
  int bound = -1;
  for (const ObjectDraw& d : list) {
    const gpu::ObjectMeshlets& o = data_.objects[d.object];
    if (o.task_count == 0) continue;
    const int want = scene_.objects[d.object].cull_back_faces ? 1 : 0;
    if (want != bound) {
      vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines[static_cast<size_t>(want)]);
      if (bound < 0)
        vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &set_, 1, &frame_offset);
      bound = want;
    }
    const gpu::PassUniforms pass{0, 0, o.first_task, 0};
    vkCmdPushConstants(cb, layout_, VK_SHADER_STAGE_TASK_BIT_EXT | VK_SHADER_STAGE_MESH_BIT_EXT, 0,
                       3 * sizeof(uint32_t), &pass);
    draw_mesh_tasks_(cb, o.task_count, 1, 1);
    ++draws;
  }
}

}  // namespace omnishadow::vk
