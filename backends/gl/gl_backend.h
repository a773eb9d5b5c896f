#pragma once
// OpenGL 4.5 core backend over headless EGL. Every technique is native GL: six_pass renders each face into a
// prebuilt per-face framebuffer; the single-pass techniques render once into a layered framebuffer.
// The class is defined over gl_backend.cpp (context, scene, case set-up), gl_support.cpp (what the context
// refuses and why), gl_passes.cpp (a frame's passes, timing and counters) and gl_readback.cpp (the checks'
// reads).

#include <epoxy/gl.h>

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend.h"
#include "backends/common/light_clusters.h"
#include "backends/common/shader_variants.h"
#include "backends/common/shadow_frame.h"
#include "backends/common/techniques.h"
#include "backends/gl/egl_context.h"
#include "backends/gl/gl_mesh_pass.h"
#include "backends/gl/gl_program.h"
#include "backends/gl/gl_queries.h"
#include "backends/gl/gl_targets.h"

namespace omnishadow::gl {

class GlBackend final : public Backend {
 public:
  void discard_tool_errors() override;
  // gl_profile: auto (core, unless that context links no passthrough geometry shader where nv_swizzle's
  // extensions are exposed and a compatibility one does: gl_passthrough.h), core or compatibility.
  GlBackend(const std::string& egl_platform, int device_index, bool api_checks,
            const std::string& gl_profile);
  ~GlBackend() override;

  Support supports(const CaseConfig& config) const override;
  std::vector<std::array<int, 6>> face_frames() const override { return planner_.face_frames(); }

 private:
  void make_current() override;  // this backend's EGL context current on the calling thread, or throws
  void create_shared_objects();
  Support all_lights_support(const CaseConfig& c) const;  // LightGrouping::all_lights's limits
  bool has_mesh_shading() const override { return has_mesh_shader_; }
  bool emulates_mesh_shading() const override { return mesh_emulation_refusal().empty(); }
  void upload_scene(const scene::Scene& scene) override;
  void upload_moving_objects() override;
  void configure_case(const CaseConfig& config) override;
  FrameTiming render_frame(int frame, FrameKind kind) override;  // each pass bracketed by glFinish
  FrameCounters count_frame_work(int frame) override;
  Images read_back_images(CubeReadBack cube, int light) override;
  void report_light(int light) override;
  struct DrawStats {
    uint64_t draw_calls = 0;
  };
  GLuint program(const std::vector<ShaderStage>& stages, const std::vector<std::string>& defines);
  // Every light's uniforms into frame_ubo_ (light k's block at k * frame_stride_) and the lighting pass's
  // light list into lights_ssbo_.
  gpu::LightFrames update_frame_uniforms(int frame);
  void upload_light_clusters(const gpu::LightFrames& f);  // --optimize clusters, timed with the lighting pass
  void bind_frame_uniforms(int light);
  DrawStats shadow_pass(const gpu::LightFrames& f);
  // One light's shadow pass into its layers of the shadow maps.
  void light_shadow_pass(int light, const gpu::ShadowFrame& f, DrawStats& stats);
  // Layout atlas: light k's block cleared, its faces drawn through their tiles' viewports.
  void atlas_light_pass(int light, const gpu::ShadowFrame& f, DrawStats& stats);
  void begin_atlas_block(int light, float far_plane);  // binds the atlas, clears light k's block
  void read_atlas_faces(int light, float near_plane, float far_plane, Images& img);
  void all_lights_shadow_pass(const gpu::LightFrames& f, DrawStats& stats);  // LightGrouping::all_lights
  // The lighting pass into lighting_[targets] with `program` (lighting_programs_[v], or floor_program_).
  DrawStats lighting_pass(gpu::LightingVariant targets, GLuint program);
  // Binds and clears render pass p's framebuffer; far_plane: this frame's light far (a world-units moments
  // clear).
  void begin_shadow_pass(int light, int p, int count, float far_plane);
  void begin_shadow_target(GLuint fbo, float far_plane);  // binds and clears one shadow framebuffer
  // The floor frame's shadow pass: every light's framebuffers cleared, nothing drawn.
  void clear_shadow_targets(const gpu::LightFrames& f);
  void map_pass(DrawStats& stats);  // one 2D map per spot/directional light
  void bind_pass_uniforms(int entry);
  // Draws one object (ObjectDraw: its index, instances and face mask).
  using DrawObject = std::function<void(const ObjectDraw& draw, const scene::Object& object)>;
  // The draws in order, each by `draw`; two_sided: closed objects keep their back faces (the two_sided
  // remedy; shadow pass only).
  void draw_list(const std::vector<ObjectDraw>& draws, DrawStats& stats, bool two_sided,
                 const DrawObject& draw);
  // The technique family's draw step (techniques.h ShadowDraw): its state set around the shadow pass (true
  // before, false after) and its draw of each object.
  struct ShadowDrawStep {
    std::function<void(bool before)> around;
    DrawObject draw;
  };
  ShadowDrawStep shadow_draw_step(const CaseConfig& c);
  // Why this context cannot run mesh_shader's emulation (empty: it can).
  std::string mesh_emulation_refusal() const;
  std::string mesh_refusal(const CaseConfig& c) const;  // native or emulated, and the launch limits
  // The emulated task stage's dispatch before a pass's draws (mesh_shader emulated; else nothing).
  void emulate_mesh_tasks();
  // nv_swizzle: viewports 0-5 take face f's swizzle (viewport_swizzle.h), or all go back to the identity.
  void set_face_swizzles(bool on);
  void release_case();
  void blur_moments(
      int light);  // the moments filters' prefilter of one light's cube, in the shadow pass's time

  void open_context(const std::string& egl_platform, int device_index, bool api_checks,
                    const std::string& gl_profile);
  std::unique_ptr<EglContext> context_;
  std::string
      passthrough_refusal_;   // why this context links no passthrough stage ("": it does, or no extension)
  std::string profile_note_;  // the context's profile and, with auto, why
  bool has_layer_array_ = false;
  bool has_multiview_ = false;  // GL_OVR_multiview2 with GL_MAX_VIEWS_OVR >= 6
  std::string
      missing_swizzle_;  // nv_swizzle: the GL_NV_ extensions it needs that are not exposed; empty: all are
  bool has_mesh_shader_ = false;           // GL_NV_mesh_shader
  std::unique_ptr<GlMeshPass> mesh_pass_;  // the scene's meshlets, from its first mesh_shader case
  ShadowDrawStep shadow_draw_;             // the configured case's
  bool has_pipeline_statistics_ = false;
  GLint uniform_alignment_ = 256;
  GLint max_vertex_storage_blocks_ = 0;
  GLint max_geometry_storage_blocks_ = 0;  // every light in one pass with the geometry shader reads the list
  GLint max_framebuffer_layers_ = 0;
  GLint max_mesh_launch_ = 0;     // GL_MAX_DRAW_MESH_TASKS_COUNT_NV: task workgroups a draw launches
  GLint max_compute_groups_ = 0;  // GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]: the emulated task stage's dispatch

  GLuint vertex_buffer_ = 0;
  GLuint shadow_vao_ = 0;    // position only
  GLuint lighting_vao_ = 0;  // position, normal, colour
  GLuint frame_ubo_ = 0;     // one FrameUniforms per light of the case, frame_stride_ apart
  GLsizeiptr frame_stride_ = 0;
  GLuint lights_ssbo_ = 0;  // gpu::PointLightRecord per light of the case
  // --optimize clusters: the case's clustered light lists, built each frame over its grid.
  GLuint clusters_ssbo_ = 0;
  gpu::LightClusterBuilder clusters_;
  GLint max_fragment_storage_blocks_ = 0, max_storage_bindings_ = 0;
  GLint max_fragment_textures_ = 0, max_combined_textures_ = 0;  // layout cube's sampler per light
  GLuint pass_ubo_ = 0;  // 64 PassUniforms {face k, mask k}, each at a multiple of uniform_alignment_
  GLuint nearest_sampler_ = 0;
  GLuint compare_sampler_ = 0;
  GLuint linear_sampler_ = 0;
  std::map<std::string, GLuint> programs_;  // by stages + defines; programs outlive cases

  ShadowTargets shadow_{};
  std::array<LightingTargets, 2> lighting_{};  // by gpu::LightingVariant: timed, check
  MapTargets maps_{};
  GLuint map_program_ = 0;
  GLuint shadow_program_ = 0;
  GLuint mesh_task_program_ = 0;               // --emulate-mesh-shader: the task stage as a compute shader
  std::array<GLuint, 2> lighting_programs_{};  // by gpu::LightingVariant
  GLuint floor_program_ = 0;                   // lighting.vert + floor.frag
  GLuint summary_program_ = 0;                 // cube_summary.comp
  GLuint blur_program_ = 0;                    // moments_blur.comp for a moments filter, else 0
  std::unique_ptr<FrameQueries> queries_;
  gpu::LightFramePlanner planner_;
};

}  // namespace omnishadow::gl
