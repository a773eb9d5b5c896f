// A frame's passes: every light's shadow passes (per face, per light, in one pass or into the atlas), the
// lighting pass, and their timing and counters.

#include "backends/common/atlas.h"
#include "backends/common/cube_faces.h"
#include "backends/common/frame_uniforms.h"
#include "backends/common/gpu_layout.h"
#include "backends/common/layouts.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"
#include "backends/common/viewport_swizzle.h"
#include "backends/gl/gl_backend.h"

namespace omnishadow::gl {

gpu::LightFrames GlBackend::update_frame_uniforms(int frame) {
  gpu::LightFrames f = planner_.prepare(*scene_, frame, *config_, cube::DepthRange::minus_one_to_one);
  if (f.atlas_replanned) shadow_.atlas = planner_.atlas();  // the passes' tiles, and the read-back's
  for (size_t k = 0; k < f.lights.size(); ++k)
    glNamedBufferSubData(frame_ubo_, GLintptr(k) * frame_stride_, sizeof(gpu::FrameUniforms),
                         &f.lights[k].uniforms);
  glNamedBufferSubData(lights_ssbo_, 0, GLsizeiptr(f.records.size() * sizeof(gpu::PointLightRecord)),
                       f.records.data());
  return f;
}

void GlBackend::upload_light_clusters(const gpu::LightFrames& f) {
  if (!clusters_ssbo_) return;
  const std::vector<uint32_t>& words = clusters_.build(f.camera, f.records);
  glNamedBufferSubData(clusters_ssbo_, 0, GLsizeiptr(words.size() * sizeof(uint32_t)), words.data());
}

// Light k's uniform block; the lighting pass binds light 0's, whose camera and knobs every light shares.
void GlBackend::bind_frame_uniforms(int light) {
  glBindBufferRange(GL_UNIFORM_BUFFER, gpu::kFrameUniformsBinding, frame_ubo_, light * frame_stride_,
                    sizeof(gpu::FrameUniforms));
}

// GL has no push constants: the pass block comes from one of 64 prebuilt ranges, entry k = {face k, mask k}.
void GlBackend::bind_pass_uniforms(int entry) {
  glBindBufferRange(GL_UNIFORM_BUFFER, gpu::kPassUniformsBinding, pass_ubo_, entry * uniform_alignment_,
                    sizeof(gpu::PassUniforms));
}

void GlBackend::draw_list(const std::vector<ObjectDraw>& draws, DrawStats& stats, bool two_sided,
                          const DrawObject& draw) {
  bool culling = false;
  glDisable(GL_CULL_FACE);
  for (const ObjectDraw& d : draws) {
    const scene::Object& obj = scene_->objects[d.object];
    const bool cull = obj.cull_back_faces && !two_sided;
    if (cull != culling) {
      culling = cull;
      culling ? glEnable(GL_CULL_FACE) : glDisable(GL_CULL_FACE);
    }
    if (d.face_mask) bind_pass_uniforms(d.face_mask);
    draw(d, obj);
    ++stats.draw_calls;
  }
}

static void draw_vertices(const ObjectDraw& d, const scene::Object& obj) {
  glDrawArraysInstanced(GL_TRIANGLES, static_cast<GLint>(obj.first_vertex),
                        static_cast<GLsizei>(obj.vertex_count), static_cast<GLsizei>(d.instances));
}

GlBackend::ShadowDrawStep GlBackend::shadow_draw_step(const CaseConfig& c) {
  switch (shadow_draw(c)) {
    case ShadowDraw::vertex_draws:
      break;
    case ShadowDraw::swizzled_viewports:  // viewports 0-5 the cube's size, each with its face's swizzle
      return {[this](bool before) { set_face_swizzles(before); }, draw_vertices};
    case ShadowDraw::mesh_tasks:  // each object's meshlets (gl_mesh_pass.h), for one light or all of them
      return {[this](bool before) {
                if (before) mesh_pass_->bind();
              },
              [this, lights = mesh_lights(c)](const ObjectDraw& d, const scene::Object&) {
                mesh_pass_->draw(d, lights);
              }};
    case ShadowDraw::emulated_mesh_tasks:  // the same, emulated (emulate_mesh_tasks dispatched them)
      return {[this](bool before) {
                if (before) mesh_pass_->bind();
              },
              [this, lights = mesh_lights(c)](const ObjectDraw& d, const scene::Object&) {
                mesh_pass_->draw_emulated(d, lights);
              }};
  }
  return {[](bool) {}, draw_vertices};
}

void GlBackend::map_pass(DrawStats& stats) {
  if (scene_->map_lights.empty()) return;
  glViewport(0, 0, maps_.size, maps_.size);
  glUseProgram(map_program_);
  const GLfloat depth_one = 1.0f;
  for (size_t i = 0; i < scene_->map_lights.size(); ++i) {
    glBindFramebuffer(GL_FRAMEBUFFER, maps_.fbos[i]);
    glClearNamedFramebufferfv(maps_.fbos[i], GL_DEPTH, 0, &depth_one);
    bind_pass_uniforms(static_cast<int>(i));
    const bool front = scene_->map_lights[i].cull_front_faces;
    for (const scene::Object& obj : scene_->objects) {
      // Closed objects: back faces culled as in the cube pass, or front faces (the directional notes'
      // peter-panning fix).
      if (obj.cull_back_faces) {
        glEnable(GL_CULL_FACE);
        glCullFace(front ? GL_FRONT : GL_BACK);
      } else {
        glDisable(GL_CULL_FACE);
      }
      glDrawArrays(GL_TRIANGLES, static_cast<GLint>(obj.first_vertex),
                   static_cast<GLsizei>(obj.vertex_count));
      ++stats.draw_calls;
    }
  }
  glCullFace(GL_BACK);
  glDisable(GL_CULL_FACE);
}

GlBackend::DrawStats GlBackend::shadow_pass(const gpu::LightFrames& frame) {
  DrawStats stats;
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glBindVertexArray(shadow_vao_);
  bind_frame_uniforms(0);
  map_pass(stats);
  glViewport(0, 0, shadow_.size, shadow_.size);
  glUseProgram(shadow_program_);
  // dual_paraboloid: each layer's pass clips the other hemisphere away (gl_ClipDistance[0],
  // shaders/paraboloid.glsl).
  const bool clip_hemisphere = traits(config_->layout).geometry.clips_to_hemisphere;
  if (clip_hemisphere) glEnable(GL_CLIP_DISTANCE0);
  if (reversed_depth_test(*config_)) glDepthFunc(GL_GREATER);
  shadow_draw_.around(true);
  if (config_->light_grouping == LightGrouping::all_lights) {
    all_lights_shadow_pass(frame, stats);
  } else {
    for (size_t k = 0; k < frame.lights.size(); ++k)
      if (!frame.lights[k].skipped())  // cached, or out of view: its map holds it already
        light_shadow_pass(static_cast<int>(k), frame.lights[k], stats);
  }
  shadow_draw_.around(false);
  glDepthFunc(GL_LESS);
  if (clip_hemisphere) glDisable(GL_CLIP_DISTANCE0);
  for (size_t k = 0; k < frame.lights.size() && blur_program_; ++k)
    if (!frame.lights[k].skipped()) blur_moments(static_cast<int>(k));
  return stats;
}

// mesh_shader's emulation: the task stage's dispatch for the pass about to draw (its frame uniforms and light
// list bound), then the shadow program again.
void GlBackend::emulate_mesh_tasks() {
  if (!mesh_task_program_) return;
  mesh_pass_->emulate_tasks(mesh_task_program_, mesh_lights(*config_));
  glUseProgram(shadow_program_);
}

// Every light in one pass: one clear of every light's layers, each object drawn once with an instance per
// light and face, the lights' view-projections from the light list (the frame was marked by
// gpu::LightFramePlanner::group_reuse: every light rendered, or none).
void GlBackend::all_lights_shadow_pass(const gpu::LightFrames& frame, DrawStats& stats) {
  if (frame.lights[0].skipped()) return;
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPointLightsBinding, lights_ssbo_);
  emulate_mesh_tasks();
  begin_shadow_target(shadow_.all_lights_fbo, frame.lights[0].uniforms.light_position.w);
  bind_pass_uniforms(0);
  const ShadowPassDraws passes = shadow_pass_draws(*config_, frame.lights[0].plan, scene_->objects.size());
  draw_list(passes.draws[0], stats, config_->remedies.two_sided, shadow_draw_.draw);
}

void GlBackend::light_shadow_pass(int light, const gpu::ShadowFrame& frame, DrawStats& stats) {
  if (shadow_.atlas) return atlas_light_pass(light, frame, stats);
  bind_frame_uniforms(light);
  emulate_mesh_tasks();
  const ShadowPassDraws passes = shadow_pass_draws(*config_, frame.plan, scene_->objects.size());
  for (int p = 0; p < passes.count; ++p) {
    if (passes.count == cube::kFaceCount && !frame.face_pass(p)) continue;  // view culling: no pass
    begin_shadow_pass(light, p, passes.count, frame.uniforms.light_position.w);
    bind_pass_uniforms(p);
    draw_list(passes.draws[static_cast<size_t>(p)], stats, config_->remedies.two_sided, shadow_draw_.draw);
  }
}

// Viewport and scissor `index` over face f's tile of light k's block: the scissor keeps every fragment inside
// the tile, whatever the rasteriser's edge rules.
static void set_tile_viewport(GLuint index, const atlas::Block& block, int face) {
  const atlas::Texel o = atlas::face_origin(block, face);
  glViewportIndexedf(index, float(o.x), float(o.y), float(block.face_size), float(block.face_size));
  glScissorIndexed(index, o.x, o.y, block.face_size, block.face_size);
}

void GlBackend::begin_atlas_block(int light, float far_plane) {
  const atlas::Block& block = shadow_.atlas->lights[size_t(light)];
  glEnable(GL_SCISSOR_TEST);  // the clear clears the light's block only: tiles and borders
  glScissor(block.x, block.y, atlas::block_width(block.face_size), atlas::block_height(block.face_size));
  begin_shadow_target(shadow_.layered_fbos[0], far_plane);
}

// six_pass: each face its own pass through viewport 0 over its tile; a single-pass technique: viewports 0-5
// over the six tiles, the face picked by gl_ViewportIndex.
void GlBackend::atlas_light_pass(int light, const gpu::ShadowFrame& frame, DrawStats& stats) {
  bind_frame_uniforms(light);
  begin_atlas_block(light, frame.uniforms.light_position.w);
  const atlas::Block& block = shadow_.atlas->lights[size_t(light)];
  const ShadowPassDraws passes = shadow_pass_draws(*config_, frame.plan, scene_->objects.size());
  for (int p = 0; p < passes.count; ++p) {
    if (passes.count > 1) set_tile_viewport(0, block, p);
    for (int f = 0; f < cube::kFaceCount && passes.count == 1; ++f) set_tile_viewport(GLuint(f), block, f);
    bind_pass_uniforms(p);
    draw_list(passes.draws[static_cast<size_t>(p)], stats, config_->remedies.two_sided, shadow_draw_.draw);
  }
  glDisable(GL_SCISSOR_TEST);
}

static_assert(GL_VIEWPORT_SWIZZLE_NEGATIVE_X_NV - GL_VIEWPORT_SWIZZLE_POSITIVE_X_NV == 1 &&
                  GL_VIEWPORT_SWIZZLE_NEGATIVE_W_NV - GL_VIEWPORT_SWIZZLE_POSITIVE_X_NV ==
                      static_cast<GLenum>(cube::SwizzleComponent::neg_w),
              "cube::SwizzleComponent counts in GL_VIEWPORT_SWIZZLE_*_NV's order");

void GlBackend::set_face_swizzles(bool on) {
  static const auto swizzles = cube::face_swizzles();  // pure: read off the face matrices once, not per frame
  auto gl_enum = [](cube::SwizzleComponent c) {
    return GL_VIEWPORT_SWIZZLE_POSITIVE_X_NV + static_cast<GLenum>(c);
  };
  for (GLuint f = 0; f < cube::kFaceCount; ++f) {
    const cube::FaceSwizzle identity{cube::SwizzleComponent::pos_x, cube::SwizzleComponent::pos_y,
                                     cube::SwizzleComponent::pos_z, cube::SwizzleComponent::pos_w};
    const cube::FaceSwizzle& s = on ? swizzles[f] : identity;
    glViewportSwizzleNV(f, gl_enum(s.x), gl_enum(s.y), gl_enum(s.z), gl_enum(s.w));
    // glViewport set every viewport already (ARB_viewport_array); said again per face, so that the six
    // viewports the mask names never depend on that.
    if (on) glViewportIndexedf(f, 0.0f, 0.0f, float(shadow_.size), float(shadow_.size));
  }
}

// The moments prefilter (shaders/moments_blur.comp): along s from the moments cube into the intermediate,
// then along t back. Image stores are incoherent: each reader waits on a barrier.
void GlBackend::blur_moments(int light) {
  glUseProgram(blur_program_);
  const atlas::Block* block = shadow_.atlas ? &shadow_.atlas->lights[size_t(light)] : nullptr;
  const int size = block ? block->face_size : shadow_.size;  // an atlas's lights have their own sizes
  glUniform1i(0, size);
  glUniform1i(2, light * shadow_.layers);
  glUniform2i(3, block ? block->x : 0, block ? block->y : 0);  // layout atlas: the light's tiles on layer 0
  glUniform1i(4, block ? atlas::tile_span(block->face_size) : 0);
  const GLuint groups = static_cast<GLuint>((size + 7) / 8);
  const GLuint from[2] = {shadow_.colour_layers, shadow_.blur_layers},
               to[2] = {shadow_.blur_layers, shadow_.colour_layers};
  for (int axis = 0; axis < 2; ++axis) {
    glBindImageTexture(0, from[axis], 0, GL_TRUE, 0, GL_READ_ONLY, shadow_.colour_format);
    glBindImageTexture(1, to[axis], 0, GL_TRUE, 0, GL_WRITE_ONLY, shadow_.colour_format);
    glUniform1i(1, axis);
    glDispatchCompute(groups, groups, static_cast<GLuint>(shadow_.layers));
    glMemoryBarrier(axis == 0 ? GL_SHADER_IMAGE_ACCESS_BARRIER_BIT
                              : GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  }
}

// Render pass p of `count`: six passes bind face p's framebuffer, one pass the layered framebuffer (whose
// clear clears all six layers); depth cleared to 1, an r32f cube to FLT_MAX ("nothing here",
// docs/glossary.md).
void GlBackend::begin_shadow_pass(int light, int p, int count, float far_plane) {
  begin_shadow_target(count > 1 ? shadow_.face_fbos[static_cast<size_t>(light * shadow_.layers + p)]
                                : shadow_.layered_fbos[static_cast<size_t>(light)],
                      far_plane);
}

void GlBackend::begin_shadow_target(GLuint fbo, float far_plane) {
  const GLfloat far_distance[4] = {FLT_MAX, FLT_MAX, FLT_MAX, FLT_MAX};
  const GLfloat depth_clear =
      reversed_depth_test(*config_) ? 0.0f : 1.0f;  // nv_swizzle's r32f: nearer is greater
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &depth_clear);
  if (shadow_.storage == Storage::r32f_distance) glClearNamedFramebufferfv(fbo, GL_COLOR, 0, far_distance);
  if (traits(shadow_.storage).moments != MomentKind::none)
    glClearNamedFramebufferfv(
        fbo, GL_COLOR, 0,
        moments_clear_value(shadow_.storage, config_->depth_format, config_->moments, far_plane).data());
}

void GlBackend::clear_shadow_targets(const gpu::LightFrames& f) {
  if (config_->light_grouping == LightGrouping::all_lights) {
    begin_shadow_target(shadow_.all_lights_fbo, f.lights[0].uniforms.light_position.w);
    return;
  }
  if (shadow_.atlas) {
    for (int k = 0; k < shadow_.lights; ++k)
      begin_atlas_block(k, f.lights[size_t(k)].uniforms.light_position.w);
    glDisable(GL_SCISSOR_TEST);
    return;
  }
  const int passes = traits(config_->technique).passes == 6 ? shadow_.layers : 1;
  for (int k = 0; k < shadow_.lights; ++k)
    for (int p = 0; p < passes; ++p)
      begin_shadow_pass(k, p, passes, f.lights[size_t(k)].uniforms.light_position.w);
}

GlBackend::DrawStats GlBackend::lighting_pass(gpu::LightingVariant variant, GLuint program) {
  DrawStats stats;
  const LightingTargets& target = lighting_[size_t(variant)];
  glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
  glViewport(0, 0, target.width, target.height);
  const GLfloat background[4] = {0.1f, 0.1f, 0.1f, 1.0f};
  const GLfloat zero[4] = {0, 0, 0, 0};
  const GLfloat depth_one = 1.0f;
  glClearNamedFramebufferfv(target.fbo, GL_COLOR, 0, background);
  if (variant == gpu::LightingVariant::check) {
    glClearNamedFramebufferfv(target.fbo, GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(target.fbo, GL_COLOR, 2, zero);
  }
  glClearNamedFramebufferfv(target.fbo, GL_DEPTH, 0, &depth_one);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glUseProgram(program);
  glBindVertexArray(lighting_vao_);
  bind_frame_uniforms(0);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kPointLightsBinding, lights_ssbo_);
  if (clusters_ssbo_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kLightClustersBinding, clusters_ssbo_);
  const LayoutLookup lookup = traits(config_->layout).lookup;
  const bool by_direction =
      lookup == LayoutLookup::hardware_cube || lookup == LayoutLookup::hardware_cube_array;
  glBindTextureUnit(gpu::kShadowMapBinding, by_direction ? shadow_.sampled : shadow_.sampled_layers);
  const FilterSampler filter_sampler = traits(config_->filter).sampler;
  const GLuint sampler = filter_sampler == FilterSampler::linear_compare   ? compare_sampler_
                         : filter_sampler == FilterSampler::linear_moments ? linear_sampler_
                                                                           : nearest_sampler_;
  glBindSampler(gpu::kShadowMapBinding, sampler);
  // Layout cube with several lights: light k's cube at unit 16 + k; the array's other elements (never read)
  // light 0's, so that every sampler the program declares has a complete texture.
  for (int k = 0; k < kLightCubes && !shadow_.light_cubes.empty(); ++k) {
    const size_t light = size_t(k) < shadow_.light_cubes.size() ? size_t(k) : 0;
    glBindTextureUnit(GLuint(gpu::kLightCubesGlUnit + k), shadow_.light_cubes[light]);
    glBindSampler(GLuint(gpu::kLightCubesGlUnit + k), sampler);
  }
  glBindTextureUnit(gpu::kMapShadowsBinding, maps_.depth);
  glBindSampler(gpu::kMapShadowsBinding, nearest_sampler_);
  draw_list(all_objects_, stats, false, draw_vertices);
  return stats;
}

FrameTiming GlBackend::render_frame(int frame, FrameKind kind) {
  const auto variant = kind == FrameKind::check ? gpu::LightingVariant::check : gpu::LightingVariant::timed;
  const GLuint program = kind == FrameKind::floor ? floor_program_ : lighting_programs_[size_t(variant)];
  // Each pass is bracketed by glFinish so that its wall time is its own. On llvmpipe the vertex and geometry
  // stages run on this thread inside glDraw*, so cpu_submit includes them; rasterisation runs on the
  // LP_NUM_THREADS worker threads and completes inside glFinish.
  std::array<HostClock::time_point, 5> t;
  t[0] = HostClock::now();
  gpu::LightFrames plan = update_frame_uniforms(frame);
  queries_->begin_timer(kShadowPass);
  if (kind == FrameKind::floor) {
    clear_shadow_targets(plan);
    planner_.forget();  // the maps no longer hold any light
  } else {
    shadow_pass(plan);
    planner_.rendered(plan, *config_);
  }
  queries_->end_timer();
  t[1] = HostClock::now();
  glFinish();
  t[2] = HostClock::now();
  queries_->begin_timer(kLightingPass);
  if (kind != FrameKind::floor) upload_light_clusters(plan);  // the floor's lighting reads no light
  lighting_pass(variant, program);
  queries_->end_timer();
  t[3] = HostClock::now();
  glFinish();
  t[4] = HostClock::now();
  if (kind == FrameKind::check) {  // the timed variant's colour of the same frame, for the timed_lit check
    lighting_pass(gpu::LightingVariant::timed, lighting_programs_[size_t(gpu::LightingVariant::timed)]);
    glFinish();
  }
  return frame_timing(t, queries_->timer_ms(kShadowPass), queries_->timer_ms(kLightingPass));
}

FrameCounters GlBackend::count_frame_work(int frame) {
  FrameCounters c;
  gpu::LightFrames plan = update_frame_uniforms(frame);
  if (queries_->has_statistics()) queries_->begin_statistics(kShadowPass);
  DrawStats shadow = shadow_pass(plan);
  planner_.rendered(plan, *config_);
  if (queries_->has_statistics()) queries_->end_statistics();
  upload_light_clusters(plan);
  if (queries_->has_statistics()) queries_->begin_statistics(kLightingPass);
  DrawStats lighting =
      lighting_pass(gpu::LightingVariant::timed, lighting_programs_[size_t(gpu::LightingVariant::timed)]);
  if (queries_->has_statistics()) queries_->end_statistics();
  glFinish();
  c.shadow = queries_->statistics(kShadowPass);
  c.lighting = queries_->statistics(kLightingPass);
  c.shadow.draw_calls = shadow.draw_calls;
  c.lighting.draw_calls = lighting.draw_calls;
  return c;
}

}  // namespace omnishadow::gl
