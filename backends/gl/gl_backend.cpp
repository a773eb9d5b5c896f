#include "backends/gl/gl_backend.h"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <chrono>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "backends/common/cube_faces.h"
#include "backends/common/cube_summary.h"
#include "backends/common/frame_uniforms.h"
#include "backends/common/gpu_layout.h"
#include "backends/common/layouts.h"
#include "backends/common/shader_variants.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"
#include "backends/common/viewport_swizzle.h"
#include "backends/gl/gl_cube_summary.h"
#include "backends/gl/gl_passthrough.h"

namespace omnishadow::gl {
namespace {

using Clock = std::chrono::steady_clock;

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

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

Support GlBackend::supports(const CaseConfig& c) const {
  const TechniqueFeature feature = traits(c.technique).feature;
  if (feature == TechniqueFeature::layer_from_vertex && !has_layer_array_)
    return {false, "GL_ARB_shader_viewport_layer_array is not exposed by " + info_.renderer};
  if (Support s = common_support(c); !s.ok) return s;
  if (feature == TechniqueFeature::multiview && !has_multiview_)
    return {false, "GL_OVR_multiview2 with 6 views is not exposed by " + info_.renderer};
  if (feature == TechniqueFeature::viewport_swizzle && !missing_swizzle_.empty() && !c.emulate_nv_swizzle)
    return {false, missing_swizzle_ + " not exposed by " + info_.renderer};
  if (feature == TechniqueFeature::viewport_swizzle && !passthrough_refusal_.empty() && !c.emulate_nv_swizzle)
    return {false, "this " + info_.api +
                       " context links no passthrough geometry shader (GL_NV_viewport_swizzle's "
                       "nv_swizzle needs one; --gl-profile auto tries a compatibility context): " +
                       passthrough_refusal_};
  if (feature == TechniqueFeature::mesh_shader)
    if (std::string why = mesh_refusal(c); !why.empty()) return {false, why};
  if (c.cube_size < 1 || c.cube_size > info_.max_cube_size)
    return {false, "cube size " + std::to_string(c.cube_size) + " outside 1.." +
                       std::to_string(info_.max_cube_size) + " (GL_MAX_CUBE_MAP_TEXTURE_SIZE)"};
  if (Support s = layer_count_support(c, std::stoi(info_.extra.at("max_array_layers")),
                                      "GL_MAX_ARRAY_TEXTURE_LAYERS");
      !s.ok)
    return s;
  if (Support s = all_lights_support(c); !s.ok) return s;
  if (c.optimizations.light_clusters &&
      (max_fragment_storage_blocks_ < 2 || max_storage_bindings_ <= gpu::kLightClustersBinding))
    return {false,
            "clustered light lists are a second storage buffer in the fragment stage at binding " +
                std::to_string(gpu::kLightClustersBinding) + ": GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS " +
                std::to_string(max_fragment_storage_blocks_) + ", GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS " +
                std::to_string(max_storage_bindings_) + " on " + info_.renderer};
  if (light_cubes(c) && (max_fragment_textures_ <= kLightCubes ||
                         max_combined_textures_ < gpu::kLightCubesGlUnit + kLightCubes))
    return {false, "layout cube with several lights samples " + std::to_string(kLightCubes + 1) +
                       " textures in the fragment stage (a cube per light and the spot maps) from unit " +
                       std::to_string(gpu::kLightCubesGlUnit) + ": GL_MAX_TEXTURE_IMAGE_UNITS " +
                       std::to_string(max_fragment_textures_) + ", GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS " +
                       std::to_string(max_combined_textures_) + " on " + info_.renderer};
  if (c.layout == Layout::atlas)
    if (std::string why = atlas::too_large(scene_ ? atlas::plan_for(c, *scene_) : atlas::uniform_plan(c),
                                           std::stoi(info_.extra.at("max_2d_size")), "GL_MAX_TEXTURE_SIZE");
        !why.empty())
      return {false, why};
  if (std::string why = atlas::budget_problem(c); !why.empty()) return {false, why};
  if (const int layer = layer_size(c.layout, c.cube_size); layer > info_.max_cube_size)
    return {false, std::string(to_string(c.layout)) + " layers of " + std::to_string(layer) +
                       " texels for cube " + std::to_string(c.cube_size) + " exceed " +
                       std::to_string(info_.max_cube_size)};
  return {};
}

// mesh_shader natively (GL_NV_mesh_shader) or emulated, and the scene's task workgroups within one launch
// (native) or one compute dispatch (emulated).
std::string GlBackend::mesh_refusal(const CaseConfig& c) const {
  if (!c.emulate_mesh_shader && !has_mesh_shader_)
    return "GL_NV_mesh_shader is not exposed by " + info_.renderer;
  if (c.emulate_mesh_shader)
    if (std::string why = mesh_emulation_refusal(); !why.empty()) return why;
  if (!meshlets_) return {};
  return gpu::mesh_launch_refusal(*meshlets_, mesh_lights(c), c.emulate_mesh_shader,
                                  uint64_t(max_mesh_launch_), "GL_MAX_DRAW_MESH_TASKS_COUNT_NV",
                                  uint64_t(max_compute_groups_), "GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]");
}

// The emulated mesh stage is a vertex shader that writes gl_Layer and reads six storage buffers: the
// meshlets, their vertices and triangles, the scene's vertices, the task entries and the light list.
std::string GlBackend::mesh_emulation_refusal() const {
  if (!has_layer_array_)
    return "mesh_shader's emulation writes gl_Layer from the vertex stage: no "
           "GL_ARB_shader_viewport_layer_array on " +
           info_.renderer;
  if (max_vertex_storage_blocks_ < 6)
    return "mesh_shader's emulation reads 6 storage buffers in the vertex stage: "
           "GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS is " +
           std::to_string(max_vertex_storage_blocks_) + " on " + info_.renderer;
  return {};
}

// Every light in one pass reads the lights' view-projections from a storage buffer in the vertex stage
// (GL 4.5 may expose none there) and renders every light's layers into one layered framebuffer.
Support GlBackend::all_lights_support(const CaseConfig& c) const {
  if (c.light_grouping != LightGrouping::all_lights) return {};
  const bool geometry = c.technique == Technique::geometry_shader;
  if ((geometry ? max_geometry_storage_blocks_ : max_vertex_storage_blocks_) < 1)
    return {false, std::string("every light in one pass reads the lights in the ") +
                       (geometry ? "geometry stage: GL_MAX_GEOMETRY_SHADER_STORAGE_BLOCKS"
                                 : "vertex stage: GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS") +
                       " is 0 on " + info_.renderer};
  if (const int layers = traits(c.layout).geometry.layers * c.light_count; layers > max_framebuffer_layers_)
    return {false, "every light in one pass renders " + std::to_string(layers) + " layers, above " +
                       "GL_MAX_FRAMEBUFFER_LAYERS " + std::to_string(max_framebuffer_layers_)};
  return {};
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

void GlBackend::discard_tool_errors() {
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

gpu::LightFrames GlBackend::update_frame_uniforms(int frame) {
  gpu::LightFrames f = planner_.prepare(*scene_, frame, *config_, cube::DepthRange::minus_one_to_one);
  for (size_t k = 0; k < f.lights.size(); ++k)
    glNamedBufferSubData(frame_ubo_, GLintptr(k) * frame_stride_, sizeof(gpu::FrameUniforms),
                         &f.lights[k].uniforms);
  glNamedBufferSubData(lights_ssbo_, 0, GLsizeiptr(f.records.size() * sizeof(gpu::PointLightRecord)),
                       f.records.data());
  return f;
}

void GlBackend::upload_light_clusters(const gpu::LightFrames& f) {
  if (!clusters_ssbo_) return;
  const std::vector<uint32_t>& words = clusters_.build(f.records);
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
  FrameTiming t;
  auto t0 = Clock::now();
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
  auto t1 = Clock::now();
  glFinish();
  auto t2 = Clock::now();
  queries_->begin_timer(kLightingPass);
  if (kind != FrameKind::floor) upload_light_clusters(plan);  // the floor's lighting reads no light
  lighting_pass(variant, program);
  queries_->end_timer();
  auto t3 = Clock::now();
  glFinish();
  auto t4 = Clock::now();
  if (kind == FrameKind::check) {  // the timed variant's colour of the same frame, for the timed_lit check
    lighting_pass(gpu::LightingVariant::timed, lighting_programs_[size_t(gpu::LightingVariant::timed)]);
    glFinish();
  }
  t.shadow = {ms_between(t0, t1), ms_between(t0, t2), queries_->timer_ms(kShadowPass)};
  t.lighting = {ms_between(t2, t3), ms_between(t2, t4), queries_->timer_ms(kLightingPass)};
  t.frame_wall_ms = ms_between(t0, t4);
  return t;
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

void GlBackend::report_light(int light) {
  const float reported = static_cast<float>(light);  // lights_info.z of light 0's block, which lighting binds
  glNamedBufferSubData(frame_ubo_, offsetof(gpu::FrameUniforms, lights_info) + 2 * sizeof(float),
                       sizeof reported, &reported);
  lighting_pass(gpu::LightingVariant::check, lighting_programs_[size_t(gpu::LightingVariant::check)]);
  glFinish();
}

static GLenum moments_format(int channels) {
  return channels == 1 ? GL_RED : channels == 2 ? GL_RG : GL_RGBA;
}

// Layout atlas: light k's six tiles, read as the faces of a cube (row 0 of a tile is t = 0, as a face's).
void GlBackend::read_atlas_faces(int light, float near_plane, float far_plane, Images& img) {
  const atlas::Block& block = shadow_.atlas->lights[size_t(light)];
  const int n = block.face_size;
  const size_t texels = size_t(n) * size_t(n);
  img.cube_size = n;
  const bool depth_stored = !traits(shadow_.storage).colour_checked;
  for (int f = 0; f < cube::kFaceCount; ++f) {
    const atlas::Texel o = atlas::face_origin(block, f);
    auto& face = img.cube_distance[size_t(f)];
    face.resize(texels);
    glGetTextureSubImage(shadow_.stored, 0, o.x, o.y, 0, n, n, 1, depth_stored ? GL_DEPTH_COMPONENT : GL_RED,
                         GL_FLOAT, static_cast<GLsizei>(texels * sizeof(float)), face.data());
    for (size_t i = 0; i < texels; ++i)
      face[i] = cube::stored_to_distance(shadow_.storage, face[i], int(i % size_t(n)), int(i / size_t(n)), n,
                                         near_plane, far_plane, cube::DepthRange::minus_one_to_one);
  }
  if (!shadow_.colour_layers) return;
  img.moment_channels = traits(shadow_.storage).colour_channels;
  for (int f = 0; f < cube::kFaceCount; ++f) {
    const atlas::Texel o = atlas::face_origin(block, f);
    auto& face = img.moments[size_t(f)];
    face.resize(texels * size_t(img.moment_channels));
    glGetTextureSubImage(shadow_.colour, 0, o.x, o.y, 0, n, n, 1, moments_format(img.moment_channels),
                         GL_FLOAT, static_cast<GLsizei>(face.size() * sizeof(float)), face.data());
  }
}

Images GlBackend::read_back_images(CubeReadBack cube_read_back, int light) {
  const LightingTargets& timed = lighting_[size_t(gpu::LightingVariant::timed)];
  const LightingTargets& check = lighting_[size_t(gpu::LightingVariant::check)];
  Images img;
  img.width = check.width;
  img.height = check.height;
  size_t pixels = static_cast<size_t>(img.width) * static_cast<size_t>(img.height);
  img.lit_rgba8.resize(pixels * 4);
  img.timed_lit_rgba8.resize(pixels * 4);
  img.shadow_factor.resize(pixels);
  img.world_position.resize(pixels * 4);
  glGetTextureImage(check.color, 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(img.lit_rgba8.size()),
                    img.lit_rgba8.data());
  glGetTextureImage(timed.color, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                    static_cast<GLsizei>(img.timed_lit_rgba8.size()), img.timed_lit_rgba8.data());
  glGetTextureImage(check.shadow_factor, 0, GL_RED, GL_FLOAT,
                    static_cast<GLsizei>(img.shadow_factor.size() * sizeof(float)), img.shadow_factor.data());
  glGetTextureImage(check.position, 0, GL_RGBA, GL_FLOAT,
                    static_cast<GLsizei>(img.world_position.size() * sizeof(float)),
                    img.world_position.data());

  img.cube_size = shadow_.size;
  size_t texels = static_cast<size_t>(shadow_.size) * static_cast<size_t>(shadow_.size);
  const bool depth_stored = !traits(shadow_.storage).colour_checked;
  // The far the light's map was rendered with (fit_range: per frame).
  const float far_plane = planner_.cube_far(light);
  const float near_plane =
      scene_->has_point_light() ? scene_->point_lights[size_t(light)].near_plane : scene_->light().near_plane;
  img.light_far = far_plane;
  const int first_layer = light * shadow_.layers;
  if (shadow_.atlas) {
    read_atlas_faces(light, near_plane, far_plane, img);  // in full: the summary's compute pass reads layers
    cube_read_back = CubeReadBack::sampled;               // (nothing more to read)
  } else if (cube_read_back == CubeReadBack::sampled) {
    read_cube_summary(summary_program_, shadow_.light_stored_layers[size_t(light)], nearest_sampler_,
                      shadow_.size, img);
    cube::sample_to_distance(img, shadow_.storage, near_plane, far_plane, cube::DepthRange::minus_one_to_one);
  }
  for (int f = 0; f < shadow_.layers && cube_read_back == CubeReadBack::full; ++f) {
    auto& face = img.cube_distance[static_cast<size_t>(f)];
    face.resize(texels);
    glGetTextureSubImage(shadow_.stored, 0, 0, 0, first_layer + f, shadow_.size, shadow_.size, 1,
                         depth_stored ? GL_DEPTH_COMPONENT : GL_RED, GL_FLOAT,
                         static_cast<GLsizei>(texels * sizeof(float)), face.data());
    const size_t n = static_cast<size_t>(shadow_.size);
    for (size_t i = 0; i < texels; ++i)
      face[i] = cube::stored_to_distance(shadow_.storage, face[i], int(i % n), int(i / n), shadow_.size,
                                         near_plane, far_plane, cube::DepthRange::minus_one_to_one);
  }
  if (shadow_.colour_layers && cube_read_back == CubeReadBack::full) {
    img.moment_channels = traits(shadow_.storage).colour_channels;
    for (int f = 0; f < 6; ++f) {
      auto& face = img.moments[static_cast<size_t>(f)];
      face.resize(texels * size_t(img.moment_channels));
      glGetTextureSubImage(shadow_.colour, 0, 0, 0, first_layer + f, shadow_.size, shadow_.size, 1,
                           moments_format(img.moment_channels), GL_FLOAT,
                           static_cast<GLsizei>(face.size() * sizeof(float)), face.data());
    }
  }
  GLenum error = glGetError();
  if (error != GL_NO_ERROR)
    throw std::runtime_error("GL error " + std::to_string(error) + " during read-back");
  if (!scene_->map_lights.empty()) {
    img.map_size = maps_.size;
    const size_t texels = size_t(maps_.size) * size_t(maps_.size);
    for (int l = 0; l < static_cast<int>(scene_->map_lights.size()); ++l) {
      std::vector<float> layer(texels);
      glGetTextureSubImage(maps_.depth, 0, 0, 0, l, maps_.size, maps_.size, 1, GL_DEPTH_COMPONENT, GL_FLOAT,
                           static_cast<GLsizei>(texels * sizeof(float)), layer.data());
      img.map_depth.push_back(std::move(layer));
    }
  }
  return img;
}

}  // namespace omnishadow::gl
