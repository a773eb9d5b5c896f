#include "backends/vulkan/vk_mesh_pass.h"

#include <cstring>
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

// The emulation's draws: one VkDrawIndirectCommand per task workgroup (shaders/shadow_mesh_task.comp).
constexpr VkDeviceSize kDrawCommandBytes = sizeof(VkDrawIndirectCommand);
constexpr VkBufferUsageFlags kEmulatedUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;

}  // namespace

VkMeshPass::VkMeshPass(VkContext& ctx, const scene::Scene& scene, const gpu::MeshletData& meshlets,
                       const Buffer& scene_vertices, const Buffer& frame_uniforms, const Buffer& point_lights)
    : ctx_(ctx), scene_(scene), data_(meshlets) {
  VkDevice d = ctx_.device();
  try {
    // The native stages where the device has them; the emulation's compute and vertex stages everywhere.
    stages_ = VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_VERTEX_BIT;
    if (ctx_.has_mesh_shader()) {
      stages_ |= VK_SHADER_STAGE_TASK_BIT_EXT | VK_SHADER_STAGE_MESH_BIT_EXT;
      draw_mesh_tasks_ =
          reinterpret_cast<PFN_vkCmdDrawMeshTasksEXT>(vkGetDeviceProcAddr(d, "vkCmdDrawMeshTasksEXT"));
      if (!draw_mesh_tasks_)
        throw std::runtime_error("vkCmdDrawMeshTasksEXT is not available on this device");
    }
    const VkDeviceSize sphere_bytes = std::max<size_t>(data_.spheres.size(), 1) * sizeof(glm::vec4);
    Buffer spheres = create_buffer(ctx_, sphere_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
    if (!data_.spheres.empty()) std::memcpy(spheres.mapped, data_.spheres.data(), size_t(sphere_bytes));
    buffers_ = {storage_buffer(ctx_, data_.meshlets), spheres, storage_buffer(ctx_, data_.vertices),
                storage_buffer(ctx_, data_.triangles)};
    for (Buffer& b : emulated_) b = create_buffer(ctx_, kDrawCommandBytes, kEmulatedUsage, false);

    std::vector<VkDescriptorSetLayoutBinding> bindings = {{gpu::kFrameUniformsBinding,
                                                           VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1,
                                                           stages_ | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
    for (int b = 0; b < gpu::kMeshBindingCount; ++b)
      bindings.push_back({static_cast<uint32_t>(gpu::kFirstMeshBinding + b),
                          VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages_, nullptr});
    for (int b : {gpu::kPointLightsBinding, gpu::kEmulatedTaskEntriesBinding, gpu::kEmulatedTaskDrawsBinding})
      bindings.push_back(
          {static_cast<uint32_t>(b), VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
           stages_ | (b == gpu::kPointLightsBinding ? VkShaderStageFlags(VK_SHADER_STAGE_FRAGMENT_BIT) : 0u),
           nullptr});
    VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    set_info.bindingCount = static_cast<uint32_t>(bindings.size());
    set_info.pBindings = bindings.data();
    OMNISHADOW_VK(vkCreateDescriptorSetLayout(d, &set_info, nullptr, &set_layout_));
    // face, face_mask, first_task: shaders/common.glsl's push block with TECHNIQUE_MESH_SHADER.
    VkPushConstantRange push{stages_, 0, 3 * sizeof(uint32_t)};
    VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout_;
    layout_info.pushConstantRangeCount = 1;
    layout_info.pPushConstantRanges = &push;
    OMNISHADOW_VK(vkCreatePipelineLayout(d, &layout_info, nullptr, &layout_));

    allocate_sets(ctx_,
                  {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1},
                   {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, static_cast<uint32_t>(gpu::kMeshBindingCount + 3)}},
                  set_layout_, 1, pool_, &set_);

    std::vector<VkDescriptorBufferInfo> infos = {{frame_uniforms.buffer, 0, sizeof(gpu::FrameUniforms)}};
    for (const Buffer& b : buffers_) infos.push_back({b.buffer, 0, VK_WHOLE_SIZE});
    infos.push_back({scene_vertices.buffer, 0, VK_WHOLE_SIZE});
    infos.push_back({point_lights.buffer, 0, VK_WHOLE_SIZE});
    std::vector<VkWriteDescriptorSet> writes(infos.size(), {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET});
    for (size_t i = 0; i < infos.size(); ++i) {
      writes[i].dstSet = set_;
      writes[i].dstBinding = bindings[i].binding;
      writes[i].descriptorCount = 1;
      writes[i].descriptorType = bindings[i].descriptorType;
      writes[i].pBufferInfo = &infos[i];
    }
    vkUpdateDescriptorSets(d, static_cast<uint32_t>(writes.size()), writes.data(), 0, nullptr);
    write_emulation_descriptors();
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
  for (Buffer& b : emulated_) destroy(ctx_, b);
}

void VkMeshPass::write_emulation_descriptors() {
  VkDescriptorBufferInfo infos[2] = {{emulated_[0].buffer, 0, VK_WHOLE_SIZE},
                                     {emulated_[1].buffer, 0, VK_WHOLE_SIZE}};
  VkWriteDescriptorSet writes[2] = {{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                    {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
  for (int i = 0; i < 2; ++i) {
    writes[i].dstSet = set_;
    writes[i].dstBinding =
        uint32_t(i == 0 ? gpu::kEmulatedTaskEntriesBinding : gpu::kEmulatedTaskDrawsBinding);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(ctx_.device(), 2, writes, 0, nullptr);
}

// The object's pipeline (back faces culled or not) where it changes, and the set with the first.
void VkMeshPass::bind_object(VkCommandBuffer cb, const std::array<VkPipeline, 2>& pipelines, uint32_t object,
                             int& bound, uint32_t frame_offset) const {
  const int want = scene_.objects[object].cull_back_faces ? 1 : 0;
  if (want == bound) return;
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines[static_cast<size_t>(want)]);
  if (bound < 0)
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &set_, 1, &frame_offset);
  bound = want;
}

// An object's task groups F .. F + n - 1 are workgroups F K .. (F + n) K - 1 for K lights
// (shaders/mesh_common.glsl, task_group and task_light): one launch natively, one indirect draw each
// emulated.
void VkMeshPass::draw_list(VkCommandBuffer cb, const std::array<VkPipeline, 2>& pipelines,
                           const std::vector<ObjectDraw>& list, uint64_t& draws, uint32_t frame_offset,
                           uint32_t lights, bool emulated) const {
  int bound = -1;
  for (const ObjectDraw& d : list) {
    const gpu::ObjectMeshlets& o = data_.objects[d.object];
    if (o.task_count == 0) continue;
    bind_object(cb, pipelines, d.object, bound, frame_offset);
    if (emulated) {
      for (uint32_t t = o.first_task * lights; t < (o.first_task + o.task_count) * lights; ++t)
        vkCmdDrawIndirect(cb, emulated_[1].buffer, t * kDrawCommandBytes, 1, uint32_t(kDrawCommandBytes));
    } else {
      const gpu::PassUniforms pass{0, 0, o.first_task * lights, 0};
      vkCmdPushConstants(cb, layout_, stages_, 0, 3 * sizeof(uint32_t), &pass);
      draw_mesh_tasks_(cb, o.task_count * lights, 1, 1);
    }
    ++draws;
  }
}

VkPipeline VkMeshPass::create_task_emulation(ShaderModules& modules, const std::string& key,
                                             uint32_t lights) {
  const uint32_t tasks = task_groups() * lights;
  if (tasks > emulated_tasks_) {
    for (Buffer& b : emulated_) destroy(ctx_, b);
    emulated_[0] = create_buffer(ctx_, VkDeviceSize(tasks) * gpu::kMeshletsPerTask * 6 * sizeof(uint32_t),
                                 kEmulatedUsage, false);
    emulated_[1] = create_buffer(ctx_, VkDeviceSize(tasks) * kDrawCommandBytes, kEmulatedUsage, false);
    emulated_tasks_ = tasks;
    write_emulation_descriptors();
  }
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = modules.get(key);
  info.stage.pName = "main";
  info.layout = layout_;
  VkPipeline pipeline = VK_NULL_HANDLE;
  OMNISHADOW_VK(vkCreateComputePipelines(ctx_.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
  return pipeline;
}

void VkMeshPass::record_emulated_tasks(VkCommandBuffer cb, VkPipeline task_pipeline, uint32_t frame_offset,
                                       uint32_t lights) const {
  const uint32_t tasks = task_groups() * lights;
  if (tasks == 0) return;
  // The previous light's draws read the entries and draws this dispatch rewrites: an execution dependency
  // orders the write after those reads.
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, nullptr, 0, nullptr, 0, nullptr);
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, task_pipeline);
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 1, &frame_offset);
  vkCmdDispatch(cb, tasks, 1, 1);
  VkMemoryBarrier written{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  written.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  written.dstAccessMask = VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT;
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT, 0, 1,
                       &written, 0, nullptr, 0, nullptr);
}

void VkMeshPass::update_spheres(const scene::Scene& posed) {
  for (const gpu::MeshletRange& r : gpu::update_moving_spheres(posed, data_))
    std::memcpy(static_cast<glm::vec4*>(buffers_[1].mapped) + r.first, &data_.spheres[r.first],
                size_t(r.count) * sizeof(glm::vec4));
}

}  // namespace omnishadow::vk
