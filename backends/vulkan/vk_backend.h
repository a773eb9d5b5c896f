#pragma once
// Vulkan backend, headless. Every technique is native Vulkan: six_pass renders the six 2D views of one
// cube-compatible image; geometry_shader / geometry_shader_instanced / vs_layer render once into a 6-layer
// framebuffer; multiview renders once with a 6-view mask.
// The class is defined over vk_backend.cpp (device objects, scene), vk_support.cpp (what the device refuses
// and why), vk_case_setup.cpp (a case's pipelines and descriptors), vk_frame.cpp (a frame's command buffers,
// timing and counters) and vk_readback.cpp (the checks' reads).

#include <vulkan/vulkan.h>

#include <array>
#include <functional>
#include <memory>
#include <optional>

#include "backends/backend.h"
#include "backends/common/light_clusters.h"
#include "backends/common/shader_variants.h"
#include "backends/common/shadow_frame.h"
#include "backends/common/techniques.h"
#include "backends/vulkan/vk_context.h"
#include "backends/vulkan/vk_cube_summary.h"
#include "backends/vulkan/vk_mesh_pass.h"
#include "backends/vulkan/vk_moments_blur.h"
#include "backends/vulkan/vk_pipelines.h"
#include "backends/vulkan/vk_resources.h"
#include "backends/vulkan/vk_targets.h"

namespace omnishadow::vk {

class VkBackend final : public Backend {
 public:
  VkBackend(const std::string& device_selector, bool validation);
  ~VkBackend() override;

  Support supports(const CaseConfig& config) const override;
  std::vector<std::array<int, 6>> face_frames() const override { return planner_.face_frames(); }
  // The validation layer's messages, collected by the context's messenger.
  std::vector<std::string> drain_api_errors() override { return ctx_->drain_messages(); }

 private:
  bool has_mesh_shading() const override { return ctx_->has_mesh_shader(); }
  bool emulates_mesh_shading() const override { return mesh_emulation_refusal().empty(); }
  // Why this device cannot run mesh_shader's emulation (empty: it can).
  std::string mesh_emulation_refusal() const;
  std::string mesh_refusal(const CaseConfig& c) const;
  std::string mesh_storage_refusal() const;
  void upload_scene(const scene::Scene& scene) override;
  void upload_moving_objects() override;
  void configure_case(const CaseConfig& config) override;
  FrameTiming render_frame(int frame, FrameKind kind) override;  // one fence-waited submission per pass
  FrameCounters count_frame_work(int frame) override;
  Images read_back_images(CubeReadBack cube, int light) override;
  void report_light(int light) override;
  // The constructor's steps.
  void describe_device(bool validation);
  void create_layouts();
  void create_descriptor_sets();
  void create_samplers_and_queries();
  // configure()'s steps.
  void create_pipelines(const CaseConfig& c);
  void write_lighting_descriptors(const CaseConfig& c);
  // Every light's shadow passes (maps first, moments blurred per light), one command buffer.
  void record_shadow(VkCommandBuffer cb, const gpu::LightFrames& frame, bool statistics, uint64_t& draws,
                     bool floor = false);
  void record_light_shadow(VkCommandBuffer cb, uint32_t light, const gpu::ShadowFrame& frame, uint64_t& draws,
                           bool floor);
  // Every light's uniform block (light k at k * frame_stride_) and the lighting pass's light list.
  void write_frame_uniforms(const gpu::LightFrames& frame);
  void record_lighting(VkCommandBuffer cb, gpu::LightingVariant variant, bool statistics, uint64_t& draws,
                       bool floor = false);
  void record_maps(VkCommandBuffer cb, uint64_t& draws);  // one 2D map per spot/directional light
  // The draws in order; a draw with a face mask (vs_layer + face culling) pushes it for the vertex shader.
  // The technique family's draw step (techniques.h ShadowDraw): how many viewports its passes set, and how it
  // records render pass `pass`'s draws (none in a floor frame).
  struct ShadowDrawStep {
    uint32_t viewports = 1;
    std::function<void(VkCommandBuffer cb, size_t pass, const std::vector<ObjectDraw>& list, uint64_t& draws,
                       bool floor)>
        record;
  };
  Support atlas_support(const CaseConfig& c) const;
  void record_atlas_light(VkCommandBuffer cb, uint32_t light, const gpu::ShadowFrame& frame,
                          VkRenderPassBeginInfo rp, uint64_t& draws, bool floor);
  void read_atlas_faces(Images& img, int light, float near_plane, float far_plane);
  ShadowDrawStep shadow_draw_step(const CaseConfig& c);
  void draw_list(VkCommandBuffer cb, const std::array<VkPipeline, 2>& pipelines, VkPipelineLayout layout,
                 VkDescriptorSet set, const std::vector<ObjectDraw>& list, uint64_t& draws);
  void begin_pass(VkCommandBuffer cb, uint32_t pass, bool statistics);  // pass 0 shadow, 1 lighting
  void end_pass(VkCommandBuffer cb, uint32_t pass, bool statistics);
  void release_case();
  void read_moments(Images& img, int light);  // a moments storage's blurred moments (full read-back)
  Support moments_support(const CaseConfig& c, const std::string& device) const;
  double timestamp_ms(uint32_t first) const;

  std::unique_ptr<VkContext> ctx_;
  std::unique_ptr<ShaderModules> modules_;
  std::unique_ptr<CubeSummarizer> summarizer_;

  VkDescriptorSetLayout shadow_set_layout_ = VK_NULL_HANDLE;    // binding 0: frame uniforms
  VkDescriptorSetLayout lighting_set_layout_ = VK_NULL_HANDLE;  // + binding 2: the shadow cube, 3: 2D maps
  // Binding 2's descriptors: kLightCubes where the device samples that many and one more in the fragment
  // stage (layout cube's sampler per light), else 1 (that layout with several lights is then refused).
  uint32_t shadow_map_descriptors_ = 1;
  VkShaderStageFlags push_stages_ = VK_SHADER_STAGE_VERTEX_BIT;  // the stages that read PassUniforms
  VkPipelineLayout shadow_layout_ = VK_NULL_HANDLE;              // + push constant: face (six_pass)
  VkPipelineLayout lighting_layout_ = VK_NULL_HANDLE;
  VkDescriptorPool descriptor_pool_ = VK_NULL_HANDLE;
  VkDescriptorSet shadow_set_ = VK_NULL_HANDLE;
  VkDescriptorSet lighting_set_ = VK_NULL_HANDLE;
  VkSampler nearest_sampler_ = VK_NULL_HANDLE;
  VkSampler compare_sampler_ = VK_NULL_HANDLE;
  VkSampler linear_sampler_ = VK_NULL_HANDLE;  // the moments filters' bilinear lookups
  // Host-visible; written before each frame, which waits for the previous one. One FrameUniforms per point
  // light (up to scene::kMaxPointLights), frame_stride_ apart: the shadow set's binding is dynamic, its
  // offset the light's block (frame_offset_ while a light's passes are recorded); lighting reads light 0's.
  Buffer frame_uniforms_;
  VkDeviceSize frame_stride_ = 0;
  uint32_t frame_offset_ = 0;
  Buffer point_lights_;  // gpu::PointLightRecord per light (host-visible), the lighting pass's binding 9
  // The case's clustered light lists (host-visible, binding 10; a header's worth without --optimize
  // clusters), built each frame over the case's grid.
  Buffer light_clusters_;
  gpu::LightClusterBuilder clusters_;
  void write_light_clusters(const gpu::LightFrames& frame);
  VkQueryPool timestamps_ = VK_NULL_HANDLE;  // 0,1: shadow pass; 2,3: lighting pass
  VkQueryPool statistics_ = VK_NULL_HANDLE;  // 0: shadow pass, 1: lighting pass
  std::array<VkCommandBuffer, 2> command_buffers_{};

  Buffer vertex_buffer_;
  // Moving casters: their posed vertices, back to back (host-visible), copied into vertex_buffer_ at the
  // start of the next shadow pass (moving_regions_), when moving_pending_.
  Buffer moving_staging_;
  std::vector<VkBufferCopy> moving_regions_;
  bool moving_pending_ = false;
  void record_moving_copy(VkCommandBuffer cb);

  ShadowTargets shadow_;
  gpu::LightFramePlanner planner_;
  std::array<LightingTargets, 2> lighting_{};  // by gpu::LightingVariant: timed, check
  MapTargets maps_;
  std::array<VkPipeline, 3>
      map_pipelines_{};  // [0] no culling, [1] back faces, [2] front faces (the directional notes)
  std::array<VkPipeline, 2> shadow_pipelines_{};                   // [0] no culling, [1] back-face culling
  std::array<std::array<VkPipeline, 2>, 2> lighting_pipelines_{};  // [variant][back-face culling]
  std::array<VkPipeline, 2> floor_pipelines_{};                    // the lighting floor, [back-face culling]
  std::unique_ptr<MomentsBlur> blur_;  // a moments filter's prefilter, recorded into the shadow pass
  std::unique_ptr<VkMeshPass>
      mesh_pass_;  // mesh_shader: the scene's meshlets, from its first mesh_shader case
  VkPipeline mesh_task_pipeline_ = VK_NULL_HANDLE;  // --emulate-mesh-shader: the task stage as compute
  ShadowDrawStep shadow_draw_;                      // the configured case's
};

}  // namespace omnishadow::vk
