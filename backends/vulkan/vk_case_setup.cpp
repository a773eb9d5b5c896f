// configure_case and its steps: the case's targets, pipelines and descriptors.
#include <algorithm>

#include "backends/common/gpu_layout.h"
#include "backends/common/shader_variants.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"
#include "backends/common/viewport_swizzle.h"
#include "backends/vulkan/vk_backend.h"

namespace omnishadow::vk {

void VkBackend::configure_case(const CaseConfig& c) {
  vkDeviceWaitIdle(ctx_->device());
  release_case();
  try {
    shadow_ = create_shadow_targets(*ctx_, c, *scene_);
    for (gpu::LightingVariant v : {gpu::LightingVariant::timed, gpu::LightingVariant::check})
      lighting_[size_t(v)] =
          create_lighting_targets(*ctx_, static_cast<uint32_t>(c.width), static_cast<uint32_t>(c.height),
                                  v == gpu::LightingVariant::check);
    // 2D maps share the cube's face size and depth format (one --cube / --depth-format axis sizes both).
    const uint32_t map_layers = static_cast<uint32_t>(scene_->map_lights.size());
    maps_ = create_map_targets(*ctx_, map_layers ? static_cast<uint32_t>(c.cube_size) : 1u,
                               std::max(map_layers, 1u), c.depth_format);
    if (traits(c.technique).stages == ShadowStages::task_mesh) {
      if (!meshlets_) throw std::logic_error("mesh_shader configured on a device without mesh shading");
      if (!mesh_pass_)
        mesh_pass_ = std::make_unique<VkMeshPass>(*ctx_, *scene_, *meshlets_, vertex_buffer_, frame_uniforms_,
                                                  point_lights_);
      // The moving casters where the scene is posed now: other techniques' frames posed it without them.
      mesh_pass_->update_spheres(*scene_);
    }
    if (shadow_draw(c) == ShadowDraw::emulated_mesh_tasks)
      mesh_task_pipeline_ = mesh_pass_->create_task_emulation(
          *modules_, gpu::variant_key(gpu::shadow_mesh_files(c).task, gpu::shadow_mesh_defines(c)),
          mesh_lights(c));
    shadow_draw_ = shadow_draw_step(c);
    create_pipelines(c);
    if (traits(c.filter).prefilter == Prefilter::separable_blur)
      blur_ = std::make_unique<MomentsBlur>(*ctx_, *modules_, colour_format(c.storage, c.depth_format),
                                            shadow_.color, shadow_.blur);
    clusters_ = gpu::LightClusterBuilder(gpu::cluster_grid(scene_->camera, c.width, c.height));
    const size_t cluster_words = c.optimizations.light_clusters
                                     ? gpu::light_cluster_words(clusters_.grid(), c.light_count)
                                     : size_t(gpu::kClusterHeaderWords);
    light_clusters_ =
        create_buffer(*ctx_, cluster_words * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
    write_lighting_descriptors(c);
  } catch (...) {
    release_case();
    throw;
  }
  config_ = c;
  planner_.reset(c.light_count, shadow_.atlas);
}

void VkBackend::create_pipelines(const CaseConfig& c) {
  PipelineDesc map;
  map.stages = {{VK_SHADER_STAGE_VERTEX_BIT, gpu::variant_key("map_depth.vert", gpu::kNoVariant)},
                {VK_SHADER_STAGE_FRAGMENT_BIT, gpu::variant_key("map_depth.frag", gpu::kNoVariant)}};
  map.layout = shadow_layout_;
  map.render_pass = maps_.render_pass;
  map.position_only = true;
  if (c.raster_perturb_steps != 0.0f)
    map.vertex_constants = {std::bit_cast<int32_t>(gpu::raster_perturb_ndc(c, info_.subpixel_bits))};
  const VkCullModeFlags map_culls[3] = {VK_CULL_MODE_NONE, VK_CULL_MODE_BACK_BIT, VK_CULL_MODE_FRONT_BIT};
  for (size_t k = 0; k < 3; ++k) {
    map.cull = map_culls[k];
    map_pipelines_[k] = create_pipeline(*ctx_, *modules_, map);
  }

  PipelineDesc shadow;
  // SPIR-V keys are "<file>:<defines joined by ','>", the names CMakeLists.txt compiled them under.
  const bool mesh = traits(c.technique).stages == ShadowStages::task_mesh;
  if (mesh && c.emulate_mesh_shader) {  // the task stage's compute pipeline: configure_case's
    shadow.stages.push_back({VK_SHADER_STAGE_VERTEX_BIT,
                             gpu::variant_key(gpu::shadow_mesh_files(c).mesh, gpu::shadow_mesh_defines(c))});
  } else if (mesh) {
    shadow.stages.push_back(
        {VK_SHADER_STAGE_TASK_BIT_EXT, gpu::variant_key("shadow_mesh.task", gpu::shadow_mesh_defines(c))});
    shadow.stages.push_back(
        {VK_SHADER_STAGE_MESH_BIT_EXT, gpu::variant_key("shadow_mesh.mesh", gpu::shadow_mesh_defines(c))});
  } else {
    shadow.stages.push_back(
        {VK_SHADER_STAGE_VERTEX_BIT, gpu::variant_key("shadow_depth.vert", gpu::shadow_vertex_defines(c))});
  }
  if (const std::string gs = gpu::shadow_geometry_file(c); !gs.empty())
    shadow.stages.push_back(
        {VK_SHADER_STAGE_GEOMETRY_BIT, gpu::variant_key(gs, gpu::shadow_geometry_defines(c))});
  shadow.stages.push_back(
      {VK_SHADER_STAGE_FRAGMENT_BIT, gpu::variant_key("shadow_depth.frag", gpu::shadow_fragment_defines(c))});
  if (shadow_draw(c) == ShadowDraw::swizzled_viewports)
    for (const cube::FaceSwizzle& f : cube::face_swizzles())
      shadow.viewport_swizzles.push_back(
          {static_cast<VkViewportCoordinateSwizzleNV>(f.x), static_cast<VkViewportCoordinateSwizzleNV>(f.y),
           static_cast<VkViewportCoordinateSwizzleNV>(f.z), static_cast<VkViewportCoordinateSwizzleNV>(f.w)});
  if (reversed_depth_test(c)) shadow.depth_compare = VK_COMPARE_OP_GREATER;
  shadow.viewports = shadow_draw_.viewports;
  shadow.layout = mesh ? mesh_pass_->layout() : shadow_layout_;
  shadow.render_pass = shadow_.render_pass;
  shadow.color_attachments = traits(c.storage).colour_channels > 0 ? 1 : 0;
  shadow.position_only = true;
  // mesh_shader's emulated vertex stage reads the meshlets' buffers, no attribute
  shadow.vertex_input = shadow_draw(c) != ShadowDraw::emulated_mesh_tasks;
  shadow.vertex_constants = map.vertex_constants;
  const gpu::LightingConstants constants = gpu::lighting_constants(c, *scene_);
  for (int cull = 0; cull < 2; ++cull) {
    // two_sided remedy: closed casters keep their back faces in the shadow pass (a light inside one is
    // blocked).
    shadow.cull = cull && !c.remedies.two_sided ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE;
    shadow_pipelines_[static_cast<size_t>(cull)] = create_pipeline(*ctx_, *modules_, shadow);
  }
  for (gpu::LightingVariant v : {gpu::LightingVariant::timed, gpu::LightingVariant::check}) {
    PipelineDesc lighting;
    lighting.stages = {
        {VK_SHADER_STAGE_VERTEX_BIT, gpu::variant_key("lighting.vert", gpu::kNoVariant)},
        {VK_SHADER_STAGE_FRAGMENT_BIT, gpu::variant_key("lighting.frag", gpu::lighting_defines(c, v))}};
    lighting.layout = lighting_layout_;
    lighting.render_pass = lighting_[size_t(v)].render_pass;
    lighting.color_attachments = static_cast<uint32_t>(gpu::kLightingColorOutputs[size_t(v)]);
    lighting.fragment_constants = {constants.map_lights, constants.point_lights, constants.injected_work,
                                   std::bit_cast<int32_t>(constants.lookup_perturb_texels),
                                   constants.light_clusters};
    for (int cull = 0; cull < 2; ++cull) {
      lighting.cull = cull ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE;
      lighting_pipelines_[size_t(v)][static_cast<size_t>(cull)] = create_pipeline(*ctx_, *modules_, lighting);
      if (v != gpu::LightingVariant::timed) continue;
      // The lighting floor: the timed target, lighting.vert with the constant floor.frag (FrameKind::floor).
      PipelineDesc floor = lighting;
      floor.stages[1].second = gpu::variant_key("floor.frag", gpu::kNoVariant);
      floor.fragment_constants.clear();
      floor_pipelines_[static_cast<size_t>(cull)] = create_pipeline(*ctx_, *modules_, floor);
    }
  }
}

void VkBackend::write_lighting_descriptors(const CaseConfig& c) {
  // Written before any command buffer binds the set: lavapipe crashes on a bound, never-written sampler.
  const FilterSampler sampler = traits(c.filter).sampler;
  const VkDescriptorImageInfo image{sampler == FilterSampler::linear_compare   ? compare_sampler_
                                    : sampler == FilterSampler::linear_moments ? linear_sampler_
                                                                               : nearest_sampler_,
                                    shadow_.sampled_view,
                                    traits(c.storage).moments != MomentKind::none
                                        ? VK_IMAGE_LAYOUT_GENERAL
                                        : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  // Every descriptor of binding 2 written (lavapipe crashes on a bound, never-written one): layout cube with
  // several lights, light k's cube in element k and light 0's in those past the last light (never read); any
  // other layout, its one view in element 0 and the same in the rest.
  std::vector<VkDescriptorImageInfo> images(shadow_map_descriptors_, image);
  for (size_t k = 0; k < images.size() && !shadow_.light_cube_views.empty(); ++k)
    images[k].imageView = shadow_.light_cube_views[k < shadow_.light_cube_views.size() ? k : 0];
  VkDescriptorImageInfo map_image{nearest_sampler_, maps_.sampled_view,
                                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  VkDescriptorBufferInfo clusters{light_clusters_.buffer, 0, VK_WHOLE_SIZE};
  VkWriteDescriptorSet writes[3] = {{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                    {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                    {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
  writes[0].dstSet = writes[1].dstSet = lighting_set_;
  writes[0].dstBinding = gpu::kShadowMapBinding;
  writes[1].dstBinding = gpu::kMapShadowsBinding;
  writes[0].descriptorCount = shadow_map_descriptors_;
  writes[1].descriptorCount = 1;
  writes[0].descriptorType = writes[1].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  writes[0].pImageInfo = images.data();
  writes[1].pImageInfo = &map_image;
  writes[2].dstSet = lighting_set_;
  writes[2].dstBinding = gpu::kLightClustersBinding;
  writes[2].descriptorCount = 1;
  writes[2].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  writes[2].pBufferInfo = &clusters;
  vkUpdateDescriptorSets(ctx_->device(), 3, writes, 0, nullptr);
}

}  // namespace omnishadow::vk
