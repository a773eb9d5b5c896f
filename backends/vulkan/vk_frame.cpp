// A frame's command buffers: the shadow passes of every light, the lighting pass, their queries and timing.
#include <cstring>

#include "backends/common/atlas.h"
#include "backends/common/cube_faces.h"
#include "backends/common/frame_uniforms.h"
#include "backends/common/gpu_layout.h"
#include "backends/common/techniques.h"
#include "backends/vulkan/vk_backend.h"

namespace omnishadow::vk {

// A pass's command buffer opens with its queries: timestamps 2 * pass and 2 * pass + 1 bracket it, and in
// count_work() the pipeline-statistics query `pass` spans it.
void VkBackend::begin_pass(VkCommandBuffer cb, uint32_t pass, bool statistics) {
  OMNISHADOW_VK(vkResetCommandBuffer(cb, 0));
  VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  OMNISHADOW_VK(vkBeginCommandBuffer(cb, &info));
  if (timestamps_) vkCmdResetQueryPool(cb, timestamps_, 2 * pass, 2);
  if (statistics) {
    vkCmdResetQueryPool(cb, statistics_, pass, 1);
    vkCmdBeginQuery(cb, statistics_, pass, 0);
  }
  if (timestamps_) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, timestamps_, 2 * pass);
}

void VkBackend::end_pass(VkCommandBuffer cb, uint32_t pass, bool statistics) {
  if (timestamps_) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps_, 2 * pass + 1);
  if (statistics) vkCmdEndQuery(cb, statistics_, pass);
  OMNISHADOW_VK(vkEndCommandBuffer(cb));
}

// Pipelines [0] for objects drawn two-sided, [1] for closed objects (back faces culled).
void VkBackend::draw_list(VkCommandBuffer cb, const std::array<VkPipeline, 2>& pipelines,
                          VkPipelineLayout layout, VkDescriptorSet set, const std::vector<ObjectDraw>& list,
                          uint64_t& draws) {
  int bound = -1;
  for (const ObjectDraw& d : list) {
    const scene::Object& obj = scene_->objects[d.object];
    if (d.face_mask) {
      const gpu::PassUniforms pass{0, d.face_mask, 0, 0};
      vkCmdPushConstants(cb, layout, push_stages_, 0, 2 * sizeof(int32_t), &pass);
    }
    int want = obj.cull_back_faces ? 1 : 0;
    if (want != bound) {
      vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines[static_cast<size_t>(want)]);
      // The shadow set's uniforms are the light's block being recorded (frame_offset_).
      const bool dynamic = set == shadow_set_;
      if (bound < 0)
        vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &set, dynamic ? 1 : 0,
                                &frame_offset_);
      bound = want;
    }
    vkCmdDraw(cb, obj.vertex_count, d.instances, obj.first_vertex, 0);
    ++draws;
  }
}

void VkBackend::record_maps(VkCommandBuffer cb, uint64_t& draws) {
  VkClearValue clear;
  clear.depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rp.renderPass = maps_.render_pass;
  rp.renderArea = {{0, 0}, {maps_.size, maps_.size}};
  rp.clearValueCount = 1;
  rp.pClearValues = &clear;
  VkViewport viewport{0, 0, float(maps_.size), float(maps_.size), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {maps_.size, maps_.size}};
  VkDeviceSize offset = 0;
  for (uint32_t i = 0; i < maps_.layers; ++i) {
    rp.framebuffer = maps_.framebuffers[i];
    vkCmdBeginRenderPass(cb, &rp, VK_SUBPASS_CONTENTS_INLINE);
    if (i < scene_->map_lights.size()) {  // else the placeholder layer: cleared only
      vkCmdSetViewport(cb, 0, 1, &viewport);
      vkCmdSetScissor(cb, 0, 1, &scissor);
      vkCmdBindVertexBuffers(cb, 0, 1, &vertex_buffer_.buffer, &offset);
      const gpu::PassUniforms pass{static_cast<int32_t>(i), 0, 0, 0};
      vkCmdPushConstants(cb, shadow_layout_, push_stages_, 0, 2 * sizeof(int32_t), &pass);
      // Closed objects: back faces culled as in the cube pass, or front faces (the directional notes'
      // peter-panning fix).
      const size_t closed = scene_->map_lights[i].cull_front_faces ? 2 : 1;
      std::array<VkPipeline, 2> pipelines = {map_pipelines_[0], map_pipelines_[closed]};
      draw_list(cb, pipelines, shadow_layout_, shadow_set_, all_objects_, draws);
    }
    vkCmdEndRenderPass(cb);
  }
}

VkBackend::ShadowDrawStep VkBackend::shadow_draw_step(const CaseConfig& c) {
  // Vertex draws: the vertex buffer, the pass's face in the push constants, each object's draw.
  auto vertex_draws = [this](VkCommandBuffer cb, size_t p, const std::vector<ObjectDraw>& list,
                             uint64_t& draws, bool floor) {
    VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cb, 0, 1, &vertex_buffer_.buffer, &offset);
    const gpu::PassUniforms pass{static_cast<int32_t>(p), 0, 0, 0};
    vkCmdPushConstants(cb, shadow_layout_, push_stages_, 0, 2 * sizeof(int32_t), &pass);
    if (!floor) draw_list(cb, shadow_pipelines_, shadow_layout_, shadow_set_, list, draws);
  };
  switch (shadow_draw(c)) {
    case ShadowDraw::vertex_draws:
      break;
    case ShadowDraw::swizzled_viewports:
      return {cube::kFaceCount, vertex_draws};
    case ShadowDraw::mesh_tasks:  // each object's meshlets (vk_mesh_pass.h), for one light or all of them
      return {1,
              [this, lights = mesh_lights(c)](VkCommandBuffer cb, size_t, const std::vector<ObjectDraw>& list,
                                              uint64_t& draws, bool floor) {
                if (!floor)
                  mesh_pass_->draw_list(cb, shadow_pipelines_, list, draws, frame_offset_, lights, false);
              }};
    case ShadowDraw::emulated_mesh_tasks:  // the same, emulated (record_light_shadow dispatched them)
      return {1,
              [this, lights = mesh_lights(c)](VkCommandBuffer cb, size_t, const std::vector<ObjectDraw>& list,
                                              uint64_t& draws, bool floor) {
                if (!floor)
                  mesh_pass_->draw_list(cb, shadow_pipelines_, list, draws, frame_offset_, lights, true);
              }};
  }
  // Layout atlas: a single pass's faces go to viewports 0-5, one per tile (gl_ViewportIndex).
  return {c.layout == Layout::atlas && traits(c.technique).passes == 1 ? uint32_t(cube::kFaceCount) : 1u,
          vertex_draws};
}

// floor: the case's render passes with their clears and nothing drawn (FrameKind::floor).
void VkBackend::record_shadow(VkCommandBuffer cb, const gpu::LightFrames& frame, bool statistics,
                              uint64_t& draws, bool floor) {
  begin_pass(cb, 0, statistics);
  record_moving_copy(cb);  // the frame's posed casters, before any pass of the frame draws them
  frame_offset_ = 0;
  if (!floor) record_maps(cb, draws);
  // Every light in one pass: its one render pass over every light's layers (the planner renders every light
  // or none).
  const bool all_lights = config_->light_grouping == LightGrouping::all_lights;
  for (uint32_t k = 0; k < (all_lights ? 1u : frame.lights.size()); ++k) {
    // A light whose map holds it already (static caching) or that is out of view is skipped; timestamps and
    // queries still close.
    if (frame.lights[k].skipped() && !floor) continue;
    frame_offset_ = static_cast<uint32_t>(k * frame_stride_);
    record_light_shadow(cb, k, frame.lights[k], draws, floor);
  }
  frame_offset_ = 0;
  // The blurs after every render pass: each binds the moments of every light (one storage view), whose
  // layers must all have left UNDEFINED.
  for (uint32_t k = 0; k < frame.lights.size() && blur_ && !floor; ++k)
    if (!frame.lights[k].skipped()) {
      const atlas::Block* block = shadow_.atlas ? &shadow_.atlas->lights[k] : nullptr;  // its own size
      blur_->record(cb, block ? uint32_t(block->face_size) : shadow_.size, k * shadow_.layers, block);
    }
  end_pass(cb, 0, statistics);
}

// One light's render passes into its layers: six_pass one per face, the others one over the light's layers.
void VkBackend::record_light_shadow(VkCommandBuffer cb, uint32_t light, const gpu::ShadowFrame& frame,
                                    uint64_t& draws, bool floor) {
  VkClearValue clears[2];
  clears[0].color = {{FLT_MAX, FLT_MAX, FLT_MAX, FLT_MAX}};   // r32f: "nothing here" (the multipass tutorial)
  if (traits(shadow_.storage).moments != MomentKind::none) {  // the moments of z = 1, as the depth's clear
    const std::array<float, 4> m = moments_clear_value(shadow_.storage, config_->depth_format,
                                                       config_->moments, frame.uniforms.light_position.w);
    clears[0].color = {{m[0], m[1], m[2], m[3]}};
  }
  clears[1].depthStencil = {reversed_depth_test(*config_) ? 0.0f : 1.0f,
                            0};  // nv_swizzle's r32f: nearer is greater
  const bool colour_first =
      traits(shadow_.storage).colour_channels > 0;  // r32f or moments: a colour attachment
  VkRenderPassBeginInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rp.renderPass = shadow_.render_pass;
  rp.renderArea = {{0, 0}, {shadow_.size, shadow_.size}};
  rp.clearValueCount = colour_first ? 2 : 1;
  rp.pClearValues = colour_first ? clears : clears + 1;
  if (shadow_.atlas) return record_atlas_light(cb, light, frame, rp, draws, floor);
  if (mesh_task_pipeline_ && !floor)  // the emulated task stage, before the render pass its draws are in
    mesh_pass_->record_emulated_tasks(cb, mesh_task_pipeline_, frame_offset_, mesh_lights(*config_));
  VkViewport viewport{0, 0, float(shadow_.size), float(shadow_.size), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {shadow_.size, shadow_.size}};
  const ShadowPassDraws passes = shadow_pass_draws(*config_, frame.plan, scene_->objects.size());
  for (size_t p = 0; p < static_cast<size_t>(passes.count); ++p) {  // six_pass: face p; else the whole cube
    if (passes.count == cube::kFaceCount && !frame.face_pass(int(p)) && !floor) continue;  // view culling
    rp.framebuffer = config_->light_grouping == LightGrouping::all_lights
                         ? shadow_.all_lights_framebuffer
                         : shadow_.framebuffers[light * static_cast<size_t>(passes.count) + p];
    vkCmdBeginRenderPass(cb, &rp, VK_SUBPASS_CONTENTS_INLINE);
    // The viewports alike (nv_swizzle's six, one per face: the pipeline's swizzles tell them apart).
    const std::array<VkViewport, cube::kFaceCount> viewports = {viewport, viewport, viewport,
                                                                viewport, viewport, viewport};
    const std::array<VkRect2D, cube::kFaceCount> scissors = {scissor, scissor, scissor,
                                                             scissor, scissor, scissor};
    vkCmdSetViewport(cb, 0, shadow_draw_.viewports, viewports.data());
    vkCmdSetScissor(cb, 0, shadow_draw_.viewports, scissors.data());
    shadow_draw_.record(cb, p, passes.draws[p], draws, floor);
    vkCmdEndRenderPass(cb);
  }
}

// Layout atlas: one render pass over light k's block (it loads: the other lights' tiles stay), the block
// cleared first, then each pass's faces through their tiles' viewports (six_pass: viewport 0 over face p's
// tile; a single pass: viewports 0-5 over the six, gl_ViewportIndex picks). Scissors are the tiles: no
// fragment leaves its tile.
void VkBackend::record_atlas_light(VkCommandBuffer cb, uint32_t light, const gpu::ShadowFrame& frame,
                                   VkRenderPassBeginInfo rp, uint64_t& draws, bool floor) {
  const atlas::Block& block = shadow_.atlas->lights[light];
  const VkRect2D area{
      {block.x, block.y},
      {uint32_t(atlas::block_width(block.face_size)), uint32_t(atlas::block_height(block.face_size))}};
  // The clear values record_light_shadow chose (colour first where there is one), as attachment clears.
  std::vector<VkClearAttachment> clears;
  for (uint32_t i = 0; i < rp.clearValueCount; ++i) {
    const bool colour = i + 1 < rp.clearValueCount;
    clears.push_back({colour ? VkImageAspectFlags(VK_IMAGE_ASPECT_COLOR_BIT)
                             : VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT),
                      0, rp.pClearValues[i]});
  }
  rp.framebuffer = shadow_.framebuffers[0];
  rp.renderArea = area;
  rp.clearValueCount = 0;
  rp.pClearValues = nullptr;
  vkCmdBeginRenderPass(cb, &rp, VK_SUBPASS_CONTENTS_INLINE);
  const VkClearRect rect{area, 0, 1};
  vkCmdClearAttachments(cb, uint32_t(clears.size()), clears.data(), 1, &rect);
  auto tile = [&](int face, VkViewport& v, VkRect2D& s) {
    const atlas::Texel o = atlas::face_origin(block, face);
    v = {float(o.x), float(o.y), float(block.face_size), float(block.face_size), 0.0f, 1.0f};
    s = {{o.x, o.y}, {uint32_t(block.face_size), uint32_t(block.face_size)}};
  };
  const ShadowPassDraws passes = shadow_pass_draws(*config_, frame.plan, scene_->objects.size());
  for (size_t p = 0; p < static_cast<size_t>(passes.count); ++p) {
    std::array<VkViewport, cube::kFaceCount> viewports{};
    std::array<VkRect2D, cube::kFaceCount> scissors{};
    for (uint32_t f = 0; f < shadow_draw_.viewports; ++f)
      tile(passes.count > 1 ? int(p) : int(f), viewports[f], scissors[f]);
    vkCmdSetViewport(cb, 0, shadow_draw_.viewports, viewports.data());
    vkCmdSetScissor(cb, 0, shadow_draw_.viewports, scissors.data());
    shadow_draw_.record(cb, p, passes.draws[p], draws, floor);
  }
  vkCmdEndRenderPass(cb);
}

void VkBackend::record_lighting(VkCommandBuffer cb, gpu::LightingVariant variant, bool statistics,
                                uint64_t& draws, bool floor) {
  const LightingTargets& target = lighting_[size_t(variant)];
  const uint32_t colors = static_cast<uint32_t>(gpu::kLightingColorOutputs[size_t(variant)]);
  begin_pass(cb, 1, statistics);
  VkClearValue clears[4];
  clears[0].color = {{0.1f, 0.1f, 0.1f, 1.0f}};  // same background as GL
  clears[1].color = {{0, 0, 0, 0}};
  clears[2].color = {{0, 0, 0, 0}};
  clears[colors].depthStencil = {1.0f, 0};  // the depth attachment follows the colour attachments
  VkRenderPassBeginInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rp.renderPass = target.render_pass;
  rp.framebuffer = target.framebuffer;
  rp.renderArea = {{0, 0}, {target.width, target.height}};
  rp.clearValueCount = colors + 1;
  rp.pClearValues = clears;
  vkCmdBeginRenderPass(cb, &rp, VK_SUBPASS_CONTENTS_INLINE);
  VkViewport viewport{0, 0, float(target.width), float(target.height), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {target.width, target.height}};
  vkCmdSetViewport(cb, 0, 1, &viewport);
  vkCmdSetScissor(cb, 0, 1, &scissor);
  VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cb, 0, 1, &vertex_buffer_.buffer, &offset);
  draw_list(cb, floor ? floor_pipelines_ : lighting_pipelines_[size_t(variant)], lighting_layout_,
            lighting_set_, all_objects_, draws);
  vkCmdEndRenderPass(cb);
  end_pass(cb, 1, statistics);
}

double VkBackend::timestamp_ms(uint32_t first) const {
  if (!timestamps_) return -1.0;
  uint64_t ticks[2] = {0, 0};
  OMNISHADOW_VK(vkGetQueryPoolResults(ctx_->device(), timestamps_, first, 2, sizeof ticks, ticks,
                                      sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  const uint32_t bits = ctx_->timestamp_valid_bits();
  const uint64_t mask = bits >= 64 ? ~0ull : ((1ull << bits) - 1);
  const uint64_t delta = ((ticks[1] & mask) - (ticks[0] & mask)) & mask;  // wraps within the valid bits
  return static_cast<double>(delta) * ctx_->properties().limits.timestampPeriod * 1e-6;
}

void VkBackend::write_frame_uniforms(const gpu::LightFrames& frame) {
  if (frame.atlas_replanned) shadow_.atlas = planner_.atlas();  // the passes' tiles, and the read-back's
  auto* base = static_cast<uint8_t*>(frame_uniforms_.mapped);
  for (size_t k = 0; k < frame.lights.size(); ++k)
    std::memcpy(base + k * frame_stride_, &frame.lights[k].uniforms, sizeof(gpu::FrameUniforms));
  std::memcpy(point_lights_.mapped, frame.records.data(),
              frame.records.size() * sizeof(gpu::PointLightRecord));
}

// The frame's clustered light lists, built on the CPU and written for the lighting pass (timed with it).
void VkBackend::write_light_clusters(const gpu::LightFrames& frame) {
  if (!config_->optimizations.light_clusters) return;
  const std::vector<uint32_t>& words = clusters_.build(frame.camera, frame.records);
  std::memcpy(light_clusters_.mapped, words.data(), words.size() * sizeof(uint32_t));
}

FrameTiming VkBackend::render_frame(int frame, FrameKind kind) {
  const auto variant = kind == FrameKind::check ? gpu::LightingVariant::check : gpu::LightingVariant::timed;
  const bool floor = kind == FrameKind::floor;
  // Each pass is its own submission, waited on before the next, so its wall time is its own (as GL's
  // glFinish). cpu_submit covers uniform update, command recording and vkQueueSubmit.
  std::array<HostClock::time_point, 5> t;
  uint64_t draws = 0;
  t[0] = HostClock::now();
  gpu::LightFrames plan = planner_.prepare(*scene_, frame, *config_, cube::DepthRange::zero_to_one);
  write_frame_uniforms(plan);
  record_shadow(command_buffers_[0], plan, false, draws, floor);
  ctx_->submit(command_buffers_[0]);
  floor ? planner_.forget() : planner_.rendered(plan, *config_);  // a floor frame leaves the maps cleared
  t[1] = HostClock::now();
  ctx_->wait();
  t[2] = HostClock::now();
  if (!floor) write_light_clusters(plan);  // the floor's lighting reads no light
  record_lighting(command_buffers_[1], variant, false, draws, floor);
  ctx_->submit(command_buffers_[1]);
  t[3] = HostClock::now();
  ctx_->wait();
  t[4] = HostClock::now();
  if (kind == FrameKind::check) {  // the timed variant's colour of the same frame, for the timed_lit check
    record_lighting(command_buffers_[1], gpu::LightingVariant::timed, false, draws);
    ctx_->submit(command_buffers_[1]);
    ctx_->wait();
  }
  return frame_timing(t, timestamp_ms(0), timestamp_ms(2));
}

FrameCounters VkBackend::count_frame_work(int frame) {
  gpu::LightFrames plan = planner_.prepare(*scene_, frame, *config_, cube::DepthRange::zero_to_one);
  write_frame_uniforms(plan);
  const bool stats = statistics_ != VK_NULL_HANDLE;
  // Mesh draws may not run inside a pipeline-statistics query that counts input-assembly, vertex or geometry
  // work (VK_EXT_mesh_shader's vkCmdDrawMeshTasksEXT), and this pool counts them: mesh_shader's shadow pass
  // is not counted.
  const bool shadow_stats = stats && shadow_draw(*config_) != ShadowDraw::mesh_tasks;
  FrameCounters c;
  record_shadow(command_buffers_[0], plan, shadow_stats, c.shadow.draw_calls);
  ctx_->submit(command_buffers_[0]);
  planner_.rendered(plan, *config_);
  ctx_->wait();
  write_light_clusters(plan);
  record_lighting(command_buffers_[1], gpu::LightingVariant::timed, stats, c.lighting.draw_calls);
  ctx_->submit(command_buffers_[1]);
  ctx_->wait();
  if (stats) {
    PassCounters* passes[2] = {&c.shadow, &c.lighting};
    for (uint32_t p = shadow_stats ? 0 : 1; p < 2; ++p) {
      uint64_t values[kPipelineStatistics.size()] = {};
      OMNISHADOW_VK(vkGetQueryPoolResults(ctx_->device(), statistics_, p, 1, sizeof values, values,
                                          sizeof values, VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
      PassCounters& k = *passes[p];
      k.valid = true;
      for (size_t s = 0; s < kPipelineStatistics.size(); ++s) k.*kPipelineStatistics[s].member = values[s];
    }
  }
  return c;
}

}  // namespace omnishadow::vk
