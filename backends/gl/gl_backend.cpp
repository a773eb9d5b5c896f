#include "backends/gl/gl_backend.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "backends/common/frame_uniforms.h"
#include "backends/common/gpu_layout.h"
#include "backends/common/layouts.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"
#include "backends/gl/gl_passthrough.h"

namespace omnishadow::gl {
namespace {

std::string gl_string(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s ? reinterpret_cast<const char*>(s) : "?";
}

// KHR_debug: keep errors and undefined behaviour (what would make a figure or an image wrong); drop the
// performance and informational chatter.
void GLAPIENTRY collect_debug_message(GLenum, GLenum type, GLuint, GLenum severity, GLsizei,
                                      const GLchar* message, const void* user) {
  if (type != GL_DEBUG_TYPE_ERROR && type != GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR &&
      severity != GL_DEBUG_SEVERITY_HIGH)
    return;
  auto* errors = static_cast<std::vector<std::string>*>(const_cast<void*>(user));
  if (errors->size() < 100) errors->emplace_back(message);
}

}  // namespace

// The context: --gl-profile's, or with auto a core one unless it links no passthrough geometry shader where
// the extension is exposed and a compatibility one does (NVIDIA: gl_passthrough.h). Why is in results.json.
void GlBackend::open_context(const std::string& egl_platform, int device_index, bool api_checks,
                             const std::string& gl_profile) {
  if (gl_profile != "auto" && gl_profile != "core" && gl_profile != "compatibility")
    throw std::runtime_error("unknown --gl-profile '" + gl_profile + "' (valid: auto, core, compatibility)");
  const auto open = [&](GlProfile p) {
    context_.reset();
    context_ = std::make_unique<EglContext>(egl_platform, device_index, api_checks, p);
  };
  open(gl_profile == "compatibility" ? GlProfile::compatibility : GlProfile::core);
  profile_note_ = gl_profile == "auto" ? "core (--gl-profile auto)" : gl_profile + " (--gl-profile)";
  if (!epoxy_has_gl_extension("GL_NV_geometry_shader_passthrough")) return;
  passthrough_refusal_ = passthrough_link_error();
  if (passthrough_refusal_.empty() || gl_profile != "auto") return;
  const std::string core_refusal = passthrough_refusal_;
  open(GlProfile::compatibility);
  passthrough_refusal_ = passthrough_link_error();
  if (passthrough_refusal_.empty()) {
    profile_note_ =
        "compatibility (--gl-profile auto: the core context links no passthrough geometry shader: " +
        core_refusal + ")";
    return;
  }
  passthrough_refusal_ = core_refusal + "; in a compatibility context too: " + passthrough_refusal_;
  open(GlProfile::core);
}

GlBackend::GlBackend(const std::string& egl_platform, int device_index, bool api_checks,
                     const std::string& gl_profile) {
  open_context(egl_platform, device_index, api_checks, gl_profile);
  GLint major = 0, minor = 0, profile_mask = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 45)
    throw std::runtime_error("OpenGL 4.5 core is required, the context is " + std::to_string(major) + "." +
                             std::to_string(minor));
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile_mask);
  info_.api = "OpenGL " + std::to_string(major) + "." + std::to_string(minor) +
              ((profile_mask & GL_CONTEXT_COMPATIBILITY_PROFILE_BIT) ? " compatibility" : " core");
  info_.extra["gl_profile"] = profile_note_;
  info_.vendor = gl_string(GL_VENDOR);
  info_.renderer = gl_string(GL_RENDERER);
  info_.version = gl_string(GL_VERSION);
  info_.platform = "EGL " + context_->egl_version() + " (" + egl_platform + ")";
  glGetIntegerv(GL_MAX_CUBE_MAP_TEXTURE_SIZE, &info_.max_cube_size);
  glGetIntegerv(GL_SUBPIXEL_BITS, &info_.subpixel_bits);
  // GL has no standard memory query: software rasterisers allocate from host memory; NVIDIA reports its
  // dedicated video memory (kB) through GL_NVX_gpu_memory_info. Elsewhere the device figure stays unknown.
  for (const char* software : {"llvmpipe", "softpipe", "swrast"})
    if (info_.renderer.find(software) != std::string::npos) info_.shares_host_memory = true;
  if (epoxy_has_gl_extension("GL_NVX_gpu_memory_info")) {
    GLint kib = 0;
    glGetIntegerv(0x9047 /* GL_GPU_MEMORY_INFO_DEDICATED_VIDMEM_NVX */, &kib);
    info_.device_memory_bytes = uint64_t(kib) * 1024;
  }
  glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &uniform_alignment_);
  GLint max_layers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
  info_.extra["max_array_layers"] = std::to_string(max_layers);
  glGetIntegerv(GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS, &max_vertex_storage_blocks_);
  glGetIntegerv(GL_MAX_GEOMETRY_SHADER_STORAGE_BLOCKS, &max_geometry_storage_blocks_);
  glGetIntegerv(GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS, &max_fragment_storage_blocks_);
  glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &max_fragment_textures_);
  glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &max_combined_textures_);
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &max_storage_bindings_);
  glGetIntegerv(GL_MAX_FRAMEBUFFER_LAYERS, &max_framebuffer_layers_);
  GLint max_texture = 0, max_renderbuffer = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_renderbuffer);
  info_.extra["max_2d_size"] = std::to_string(std::min(max_texture, max_renderbuffer));
  has_layer_array_ = epoxy_has_gl_extension("GL_ARB_shader_viewport_layer_array");
  has_pipeline_statistics_ = epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query");
  GLint max_views = 0;
  if (epoxy_has_gl_extension("GL_OVR_multiview2")) glGetIntegerv(GL_MAX_VIEWS_OVR, &max_views);
  has_multiview_ = max_views >= 6;
  for (const char* ext :
       {"GL_NV_viewport_swizzle", "GL_NV_viewport_array2", "GL_NV_geometry_shader_passthrough"})
    if (!epoxy_has_gl_extension(ext))
      missing_swizzle_ += (missing_swizzle_.empty() ? "" : ", ") + std::string(ext);
  has_mesh_shader_ = epoxy_has_gl_extension("GL_NV_mesh_shader");
  if (has_mesh_shader_) glGetIntegerv(GL_MAX_DRAW_MESH_TASKS_COUNT_NV, &max_mesh_launch_);
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &max_compute_groups_);
  info_.extra["nv_swizzle extensions"] = missing_swizzle_.empty() ? "yes" : "missing " + missing_swizzle_;
  info_.extra["GL_NV_mesh_shader"] = has_mesh_shader_ ? "yes" : "no";
  info_.extra["GL_ARB_shader_viewport_layer_array"] = has_layer_array_ ? "yes" : "no";
  info_.extra["GL_OVR_multiview2"] = max_views > 0 ? "yes, " + std::to_string(max_views) + " views" : "no";
  info_.extra["GL_ARB_pipeline_statistics_query"] = has_pipeline_statistics_ ? "yes" : "no";
  info_.extra["GL_SHADING_LANGUAGE_VERSION"] = gl_string(GL_SHADING_LANGUAGE_VERSION);
  info_.extra["api_checks"] = api_checks ? "KHR_debug errors captured (debug context)" : "off";
  if (api_checks) {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);  // messages arrive before the call returns: attributable to a case
    glDebugMessageCallback(collect_debug_message, &api_errors_);
  }
  create_shared_objects();
}

// What every case uses: the frame and pass uniform buffers, the three samplers, and the state set once.
void GlBackend::create_shared_objects() {
  std::vector<uint8_t> pass_data(static_cast<size_t>(uniform_alignment_) * gpu::kPassUniformEntries, 0);
  for (int k = 0; k < gpu::kPassUniformEntries; ++k) {
    gpu::PassUniforms p{k, static_cast<uint32_t>(k), 0, 0};
    std::memcpy(pass_data.data() + static_cast<size_t>(k * uniform_alignment_), &p, sizeof p);
  }
  glCreateBuffers(1, &pass_ubo_);
  glNamedBufferStorage(pass_ubo_, static_cast<GLsizeiptr>(pass_data.size()), pass_data.data(), 0);

  glCreateSamplers(1, &nearest_sampler_);
  glSamplerParameteri(nearest_sampler_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glSamplerParameteri(nearest_sampler_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glCreateSamplers(1, &compare_sampler_);
  glSamplerParameteri(compare_sampler_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glSamplerParameteri(compare_sampler_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glSamplerParameteri(compare_sampler_, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glSamplerParameteri(compare_sampler_, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glCreateSamplers(1, &linear_sampler_);  // moments: filtered bilinearly, as VSM intends
  glSamplerParameteri(linear_sampler_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glSamplerParameteri(linear_sampler_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLuint s : {nearest_sampler_, compare_sampler_, linear_sampler_}) {
    glSamplerParameteri(s, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(s, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(s, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  }
  // Cube faces are filtered across seams, as every modern GPU can; keeps PCF continuous at face edges.
  glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
}

GlBackend::~GlBackend() {
  // Without a current context every GL call below would go to libepoxy's resolver, which aborts the process;
  // destroying the EGL context (EglContext's destructor) frees these objects anyway.
  if (!context_->make_current()) {
    (void)queries_.release();    // its destructor deletes GL queries: left to the context's destruction
    (void)mesh_pass_.release();  // and its buffers
    return;
  }
  release_case();
  mesh_pass_.reset();
  for (auto& [key, prog] : programs_) glDeleteProgram(prog);
  const GLuint buffers[] = {vertex_buffer_, pass_ubo_};
  glDeleteBuffers(2, buffers);
  const GLuint vaos[] = {shadow_vao_, lighting_vao_};
  glDeleteVertexArrays(2, vaos);
  const GLuint samplers[] = {nearest_sampler_, compare_sampler_, linear_sampler_};
  glDeleteSamplers(3, samplers);
}

void GlBackend::upload_scene(const scene::Scene& scene) {
  release_case();
  mesh_pass_.reset();
  glDeleteBuffers(1, &vertex_buffer_);
  const GLuint vaos[] = {shadow_vao_, lighting_vao_};
  glDeleteVertexArrays(2, vaos);

  glCreateBuffers(1, &vertex_buffer_);
  // Moving casters are rewritten every frame (upload_moving_objects); a static scene's buffer never changes.
  glNamedBufferStorage(vertex_buffer_, static_cast<GLsizeiptr>(scene.vertices.size() * sizeof(scene::Vertex)),
                       scene.vertices.data(), scene.has_moving_objects() ? GL_DYNAMIC_STORAGE_BIT : 0);
  if (glGetError() == GL_OUT_OF_MEMORY)
    throw std::runtime_error("GL_OUT_OF_MEMORY uploading scene " + scene.name);

  auto make_vao = [&](bool with_attributes) {
    GLuint vao = 0;
    glCreateVertexArrays(1, &vao);
    glVertexArrayVertexBuffer(vao, 0, vertex_buffer_, 0, static_cast<GLsizei>(gpu::kVertexStride));
    const std::pair<GLuint, size_t> attributes[] = {
        {0, gpu::kPositionOffset}, {1, gpu::kNormalOffset}, {2, gpu::kColorOffset}};
    for (const auto& [location, offset] : attributes) {
      if (location > 0 && !with_attributes) break;
      glEnableVertexArrayAttrib(vao, location);
      glVertexArrayAttribFormat(vao, location, 3, GL_FLOAT, GL_FALSE, static_cast<GLuint>(offset));
      glVertexArrayAttribBinding(vao, location, 0);
    }
    return vao;
  };
  shadow_vao_ = make_vao(false);
  lighting_vao_ = make_vao(true);
}

// GL calls go to the thread's current context: another backend brought up on this thread made its own
// current, one torn down left none (libepoxy aborts on a call without one). A check of the current context,
// cheap enough for every frame.
void GlBackend::make_current() {
  if (!context_->make_current())
    throw std::runtime_error(
        "eglMakeCurrent failed: the OpenGL backend's context cannot be made current on "
        "this thread");
}

void GlBackend::discard_tool_errors() {
  make_current();
  for (int i = 0; i < 64 && glGetError() != GL_NO_ERROR; ++i) {
  }
}

void GlBackend::upload_moving_objects() {
  for (const scene::Object& o : scene_->objects)
    if (o.moves())
      glNamedBufferSubData(vertex_buffer_, GLintptr(o.first_vertex) * GLintptr(sizeof(scene::Vertex)),
                           GLsizeiptr(o.vertex_count) * GLsizeiptr(sizeof(scene::Vertex)),
                           &scene_->vertices[o.first_vertex]);
  if (mesh_pass_ && config_ && traits(config_->technique).stages == ShadowStages::task_mesh)
    mesh_pass_->update_spheres(*scene_);
}

GLuint GlBackend::program(const std::vector<ShaderStage>& stages, const std::vector<std::string>& defines) {
  std::string key;
  for (const auto& s : stages) key += s.file + ";";
  for (const auto& d : defines) key += d + ";";
  auto it = programs_.find(key);
  if (it != programs_.end()) return it->second;
  GLuint p = build_program(stages, defines);
  programs_[key] = p;
  return p;
}

void GlBackend::release_case() {
  queries_.reset();
  if (shadow_.depth) destroy(shadow_);
  for (LightingTargets& t : lighting_)
    if (t.fbo) destroy(t);
  if (maps_.depth) destroy(maps_);
  const GLuint buffers[] = {frame_ubo_, lights_ssbo_, clusters_ssbo_};
  glDeleteBuffers(3, buffers);
  frame_ubo_ = lights_ssbo_ = clusters_ssbo_ = 0;
  config_.reset();
}

void GlBackend::configure_case(const CaseConfig& c) {
  release_case();

  const ProgramSource shadow_source = shadow_program_source(c, info_.subpixel_bits);
  shadow_program_ = program(shadow_source.stages, shadow_source.defines);
  std::vector<std::string> map_defines;
  if (c.raster_perturb_steps != 0.0f) {
    char perturb[64];
    std::snprintf(perturb, sizeof perturb, "RASTER_PERTURB_NDC=%.9g",
                  gpu::raster_perturb_ndc(c, info_.subpixel_bits));
    map_defines.push_back(perturb);
  }
  if (traits(c.technique).stages == ShadowStages::task_mesh) {
    if (!meshlets_) throw std::logic_error("mesh_shader configured on a device without mesh shading");
    if (!mesh_pass_)
      mesh_pass_ =
          std::make_unique<GlMeshPass>(*meshlets_, vertex_buffer_);  // once per scene: outlives cases
    // The moving casters where the scene is posed now: other techniques' frames posed it without them.
    mesh_pass_->update_spheres(*scene_);
  }
  mesh_task_program_ = 0;
  if (shadow_draw(c) == ShadowDraw::emulated_mesh_tasks)
    mesh_task_program_ =
        program({{GL_COMPUTE_SHADER, gpu::shadow_mesh_files(c).task}}, gpu::shadow_mesh_defines(c));
  shadow_draw_ = shadow_draw_step(c);
  for (gpu::LightingVariant v : {gpu::LightingVariant::timed, gpu::LightingVariant::check}) {
    std::vector<std::string> defines = gpu::lighting_defines(c, v);
    for (std::string& d : gpu::lighting_constant_defines(gpu::lighting_constants(c, *scene_)))
      defines.push_back(d);
    lighting_programs_[size_t(v)] =
        program({{GL_VERTEX_SHADER, "lighting.vert"}, {GL_FRAGMENT_SHADER, "lighting.frag"}}, defines);
  }

  map_program_ =
      program({{GL_VERTEX_SHADER, "map_depth.vert"}, {GL_FRAGMENT_SHADER, "map_depth.frag"}}, map_defines);
  floor_program_ = program({{GL_VERTEX_SHADER, "lighting.vert"}, {GL_FRAGMENT_SHADER, "floor.frag"}}, {});
  summary_program_ = program({{GL_COMPUTE_SHADER, "cube_summary.comp"}}, {});
  blur_program_ = 0;
  if (traits(c.filter).prefilter == Prefilter::separable_blur)
    blur_program_ = program({{GL_COMPUTE_SHADER, "moments_blur.comp"}},
                            gpu::moments_blur_defines(colour_format(c.storage, c.depth_format)));
  shadow_ = create_shadow_targets(
      {layer_size(c.layout, c.cube_size), c.storage, c.depth_format, traits(c.technique).multiview,
       traits(c.layout).geometry.layers, c.light_count,
       traits(c.layout).lookup == LayoutLookup::hardware_cube_array,
       c.layout == Layout::atlas ? std::optional(atlas::plan_for(c, *scene_)) : std::nullopt,
       light_cubes(c)});
  // One uniform block per light (the shadow pass binds light k's), and the lighting pass's light list.
  frame_stride_ = (GLsizeiptr(sizeof(gpu::FrameUniforms)) + uniform_alignment_ - 1) / uniform_alignment_ *
                  uniform_alignment_;
  glCreateBuffers(1, &frame_ubo_);
  glNamedBufferStorage(frame_ubo_, frame_stride_ * c.light_count, nullptr, GL_DYNAMIC_STORAGE_BIT);
  glCreateBuffers(1, &lights_ssbo_);
  glNamedBufferStorage(lights_ssbo_, GLsizeiptr(sizeof(gpu::PointLightRecord)) * c.light_count, nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  if (c.optimizations.light_clusters) {
    clusters_ = gpu::LightClusterBuilder(gpu::cluster_grid(scene_->camera, c.width, c.height));
    glCreateBuffers(1, &clusters_ssbo_);
    glNamedBufferStorage(
        clusters_ssbo_,
        GLsizeiptr(gpu::light_cluster_words(clusters_.grid(), c.light_count) * sizeof(uint32_t)), nullptr,
        GL_DYNAMIC_STORAGE_BIT);
  }
  // 2D maps share the cube's face size and depth format, so one --cube / --depth-format axis sizes both.
  maps_ = create_map_targets(c.cube_size, static_cast<int>(scene_->map_lights.size()), c.depth_format);
  lighting_[size_t(gpu::LightingVariant::timed)] = create_lighting_targets(c.width, c.height, false);
  lighting_[size_t(gpu::LightingVariant::check)] = create_lighting_targets(c.width, c.height, true);
  queries_ = std::make_unique<FrameQueries>(has_pipeline_statistics_);
  GLenum error = glGetError();
  if (error != GL_NO_ERROR) {
    release_case();
    throw std::runtime_error("GL error " + std::to_string(error) + " while configuring " + c.id());
  }
  config_ = c;
  planner_.reset(c.light_count, shadow_.atlas);
}

}  // namespace omnishadow::gl
