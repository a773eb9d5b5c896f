#include "backends/vulkan/vk_pipelines.h"

#include <algorithm>

#include "backends/common/gpu_layout.h"
#include "backends/vulkan/vk_spirv.h"

namespace omnishadow::vk {

ShaderModules::~ShaderModules() {
  for (auto& [key, module] : modules_) vkDestroyShaderModule(ctx_.device(), module, nullptr);
}

VkShaderModule ShaderModules::get(const std::string& key) {
  auto it = modules_.find(key);
  if (it != modules_.end()) return it->second;
  auto code = embedded_spirv().find(key);
  if (code == embedded_spirv().end())
    throw std::runtime_error("SPIR-V variant '" + key + "' was not compiled");
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = code->second.size() * sizeof(uint32_t);
  info.pCode = code->second.data();
  VkShaderModule module = VK_NULL_HANDLE;
  OMNISHADOW_VK(vkCreateShaderModule(ctx_.device(), &info, nullptr, &module));
  modules_[key] = module;
  return module;
}

namespace {

// Constant k at offset 4k, 4 bytes each. `entries` must outlive the returned info's use.
VkSpecializationInfo specialisation_of(const std::vector<int32_t>& values,
                                       std::vector<VkSpecializationMapEntry>& entries) {
  for (uint32_t k = 0; k < values.size(); ++k)
    entries.push_back({k, static_cast<uint32_t>(k * sizeof(int32_t)), sizeof(int32_t)});
  return {static_cast<uint32_t>(entries.size()), entries.data(), values.size() * sizeof(int32_t),
          values.data()};
}

// desc's stages, each with the specialisation constants it reads: the fragment stage its own, the stages that
// place vertices (vertex, geometry, mesh) the raster perturbation's. The infos point at `fragment` and
// `vertex`.
std::vector<VkPipelineShaderStageCreateInfo> stage_infos(ShaderModules& modules, const PipelineDesc& desc,
                                                         const VkSpecializationInfo& fragment,
                                                         const VkSpecializationInfo& vertex) {
  std::vector<VkPipelineShaderStageCreateInfo> stages;
  for (const auto& [stage, key] : desc.stages) {
    VkPipelineShaderStageCreateInfo s{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    s.stage = stage;
    s.module = modules.get(key);
    s.pName = "main";
    if (stage == VK_SHADER_STAGE_FRAGMENT_BIT && fragment.mapEntryCount > 0)
      s.pSpecializationInfo = &fragment;
    if ((stage == VK_SHADER_STAGE_VERTEX_BIT || stage == VK_SHADER_STAGE_GEOMETRY_BIT ||
         stage == VK_SHADER_STAGE_MESH_BIT_EXT) &&
        vertex.mapEntryCount > 0)
      s.pSpecializationInfo = &vertex;
    stages.push_back(s);
  }
  return stages;
}

}  // namespace

VkPipeline create_pipeline(VkContext& ctx, ShaderModules& modules, const PipelineDesc& desc) {
  std::vector<VkSpecializationMapEntry> fragment_entries, vertex_entries;
  const VkSpecializationInfo fragment = specialisation_of(desc.fragment_constants, fragment_entries);
  const VkSpecializationInfo vertex = specialisation_of(desc.vertex_constants, vertex_entries);
  const std::vector<VkPipelineShaderStageCreateInfo> stages = stage_infos(modules, desc, fragment, vertex);
  const bool mesh_pipeline =
      std::any_of(stages.begin(), stages.end(), [](const VkPipelineShaderStageCreateInfo& s) {
        return s.stage ==
               VK_SHADER_STAGE_MESH_BIT_EXT;  // task + mesh stages: no vertex input or input assembly
      });
  VkVertexInputBindingDescription binding{0, static_cast<uint32_t>(gpu::kVertexStride),
                                          VK_VERTEX_INPUT_RATE_VERTEX};
  VkVertexInputAttributeDescription attributes[] = {
      {0, 0, VK_FORMAT_R32G32B32_SFLOAT, static_cast<uint32_t>(gpu::kPositionOffset)},
      {1, 0, VK_FORMAT_R32G32B32_SFLOAT, static_cast<uint32_t>(gpu::kNormalOffset)},
      {2, 0, VK_FORMAT_R32G32B32_SFLOAT, static_cast<uint32_t>(gpu::kColorOffset)}};
  VkPipelineVertexInputStateCreateInfo vertex_input{
      VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vertex_input.vertexBindingDescriptionCount = desc.vertex_input ? 1 : 0;
  vertex_input.pVertexBindingDescriptions = &binding;
  vertex_input.vertexAttributeDescriptionCount = !desc.vertex_input ? 0 : desc.position_only ? 1 : 3;
  vertex_input.pVertexAttributeDescriptions = attributes;
  VkPipelineInputAssemblyStateCreateInfo assembly{
      VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  const uint32_t viewports =
      desc.viewport_swizzles.empty() ? desc.viewports : static_cast<uint32_t>(desc.viewport_swizzles.size());
  viewport.viewportCount = viewports;
  viewport.scissorCount = viewports;
  VkPipelineViewportSwizzleStateCreateInfoNV swizzle{
      VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_SWIZZLE_STATE_CREATE_INFO_NV};
  if (!desc.viewport_swizzles.empty()) {
    swizzle.viewportCount = viewports;
    swizzle.pViewportSwizzles = desc.viewport_swizzles.data();
    viewport.pNext = &swizzle;
  }
  VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = desc.cull;
  // Clip space is not flipped (cube_faces.h), so framebuffer rows match GL's window rows; Vulkan's
  // signed-area formula has the opposite sign of GL's, hence clockwise here for GL's counter-clockwise.
  raster.frontFace = VK_FRONT_FACE_CLOCKWISE;
  raster.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  depth.depthTestEnable = VK_TRUE;
  depth.depthWriteEnable = VK_TRUE;
  depth.depthCompareOp = desc.depth_compare;
  std::vector<VkPipelineColorBlendAttachmentState> blend(desc.color_attachments);
  for (auto& b : blend)
    b.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                       VK_COLOR_COMPONENT_A_BIT;
  VkPipelineColorBlendStateCreateInfo color{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  color.attachmentCount = desc.color_attachments;
  color.pAttachments = blend.data();
  VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamic_states;

  VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  info.stageCount = static_cast<uint32_t>(stages.size());
  info.pStages = stages.data();
  info.pVertexInputState = mesh_pipeline ? nullptr : &vertex_input;
  info.pInputAssemblyState = mesh_pipeline ? nullptr : &assembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth;
  info.pColorBlendState = &color;
  info.pDynamicState = &dynamic;
  info.layout = desc.layout;
  info.renderPass = desc.render_pass;
  VkPipeline pipeline = VK_NULL_HANDLE;
  OMNISHADOW_VK(vkCreateGraphicsPipelines(ctx.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
  return pipeline;
}

ComputePipeline create_compute_pipeline(VkContext& ctx, ShaderModules& modules, const std::string& key,
                                        const std::vector<VkDescriptorType>& bindings, uint32_t push_bytes) {
  VkDevice d = ctx.device();
  ComputePipeline p;
  try {
    std::vector<VkDescriptorSetLayoutBinding> described;
    for (uint32_t b = 0; b < bindings.size(); ++b)
      described.push_back({b, bindings[b], 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    set_info.bindingCount = static_cast<uint32_t>(described.size());
    set_info.pBindings = described.data();
    OMNISHADOW_VK(vkCreateDescriptorSetLayout(d, &set_info, nullptr, &p.set_layout));
    VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
    VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &p.set_layout;
    layout_info.pushConstantRangeCount = push_bytes ? 1 : 0;
    layout_info.pPushConstantRanges = &push;
    OMNISHADOW_VK(vkCreatePipelineLayout(d, &layout_info, nullptr, &p.layout));
    VkComputePipelineCreateInfo pipeline_info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    pipeline_info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    pipeline_info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pipeline_info.stage.module = modules.get(key);
    pipeline_info.stage.pName = "main";
    pipeline_info.layout = p.layout;
    OMNISHADOW_VK(vkCreateComputePipelines(d, VK_NULL_HANDLE, 1, &pipeline_info, nullptr, &p.pipeline));
  } catch (...) {
    destroy(ctx, p);
    throw;
  }
  return p;
}

void destroy(VkContext& ctx, ComputePipeline& p) {
  VkDevice d = ctx.device();
  if (p.pipeline) vkDestroyPipeline(d, p.pipeline, nullptr);
  if (p.layout) vkDestroyPipelineLayout(d, p.layout, nullptr);
  if (p.set_layout) vkDestroyDescriptorSetLayout(d, p.set_layout, nullptr);
  p = ComputePipeline{};
}

}  // namespace omnishadow::vk
