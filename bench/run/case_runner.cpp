#include "bench/run/case_runner.h"

#include <algorithm>
#include <bit>
#include <chrono>

#include "backends/common/cube_faces.h"
#include "backends/common/driver_log.h"
#include "backends/common/layouts.h"
#include "backends/common/shadow_plan.h"
#include "backends/common/view_culling.h"
#include "bench/io/image_io.h"
#include "bench/run/case_progress.h"
#include "bench/run/memory_budget.h"
#include "bench/run/renderdoc_frames.h"
#include "bench/run/scripted_clock.h"
#include "bench/run/timing_stats.h"

namespace omnishadow::bench {

CubeReadBack Harness::cube_read_back_for(const CaseConfig& c) const {
  using P = RunOptions::CubeReadBackPolicy;
  // The cube summary's compute shader walks six cube faces; other layouts' layers are read in full.
  if (traits(c.layout).geometry.map != TexelMap::cube_faces) return CubeReadBack::full;
  switch (options_.cube_read_back) {
    case P::full:
      return CubeReadBack::full;
    case P::sampled:
      return CubeReadBack::sampled;
    case P::automatic:
      break;
  }
  const bool small = c.cube_size <= RunOptions::kFullCubeReadBackMax;
  return small || options_.images == RunOptions::ImagePolicy::all ? CubeReadBack::full
                                                                  : CubeReadBack::sampled;
}

// The case's check frame again, its cube read in full into `images` (for a value-by-value comparison once
// hashes differed). Rendering is deterministic, so it is the frame already checked; the floor frame cleared
// the cube since.
// Light `light`'s images of the frame just rendered, with the faces that frame drew (view culling).
Images Harness::read_light(Backend& b, const CaseConfig& c, int light) {
  Images img = b.read_back(cube_read_back_for(c), light);
  if (!c.optimizations.view_culling) return img;
  scene::Scene& sc = const_cast<scene::Scene&>(scene_of(c));  // not a const object: focus only
  scene::FocusLight focus(sc, light);
  img.view_faces = gpu::view_faces(sc, c, options_.check_frame, img.light_far, img.cube_size);
  return img;
}

void Harness::read_full_cube(const CaseConfig& c, Images& images, int light) {
  Backend& b = activate(c);
  b.render(options_.check_frame, FrameKind::check);
  images.cube_distance = b.read_back(CubeReadBack::full, light).cube_distance;
}

Harness::Harness(RunOptions options)
    : options_(std::move(options)), scenes_(options_.scenes_dir, options_.light, options_.camera) {
  if (options_.async_images) writer_ = std::make_unique<AsyncWriter>();
}

void Harness::write_later(const CaseResult& r, std::function<void()> write) {
  if (writer_)
    writer_->submit(r.config.id(), std::move(write));
  else
    write();
}

std::vector<std::pair<std::string, std::string>> Harness::drain_writes() {
  return writer_ ? writer_->drain() : std::vector<std::pair<std::string, std::string>>{};
}
// Backends go in the reverse order of their creation (a map would destroy them by name): each API's teardown
// then runs while what it was created after still stands.
Harness::~Harness() {
  for (auto it = creation_order_.rbegin(); it != creation_order_.rend(); ++it) backends_.erase(*it);
}

Backend& Harness::backend(const std::string& name) {
  auto it = backends_.find(name);
  if (it != backends_.end()) return *it->second;
  auto created = create_backend(name, options_.backend_options);
  Backend& ref = *created;
  backends_[name] = std::move(created);
  creation_order_.push_back(name);
  return ref;
}

DeviceStateProbe& Harness::probe(const std::string& name) {
  auto it = probes_.find(name);
  if (it == probes_.end()) it = probes_.emplace(name, make_device_state_probe(backend(name).device())).first;
  return *it->second;
}

DeviceState Harness::sample_device(const std::string& name) { return probe(name).sample(); }
std::string Harness::device_state_source(const std::string& name) { return probe(name).source(); }
std::string Harness::lock_clocks(const std::string& name) { return probe(name).lock_clocks(); }

void Harness::add_backend(const std::string& name, std::unique_ptr<Backend> backend) {
  probes_.erase(name);
  backends_[name] = std::move(backend);
  std::erase(creation_order_, name);
  creation_order_.push_back(name);
  loaded_scene_.erase(name);
}

std::string Harness::add_scene(const std::string& name_or_path) { return scenes_.add(name_or_path); }

const scene::Scene& Harness::scene(const std::string& name, bool rebase_origin, int tessellation) {
  return scenes_.get(name, rebase_origin, tessellation);
}

Backend& Harness::activate(const CaseConfig& config) {
  Backend& b = backend(config.backend);
  const std::string key = scene_key(config);
  if (loaded_scene_[config.backend] != key) {
    loaded_scene_[config.backend].clear();
    b.load(scene_of(config));
    loaded_scene_[config.backend] = key;
  }
  b.configure(config);
  return b;
}

// Whether the case can run here at all: supported by the backend and the scene, and (unless told not to
// check) fitting in memory. Adds the finding that says why not.
bool Harness::admit(CaseResult& r, Backend& b) {
  const scene::Scene& sc = scene_of(r.config);
  Support s = r.config.light_count > std::max<int>(int(sc.point_lights.size()), 1)
                  ? Support{false, r.config.scene + " has " + std::to_string(sc.point_lights.size()) +
                                       " point light(s); --light-count " +
                                       std::to_string(r.config.light_count) + " asks for more"}
                  : b.supports(r.config);
  if (s.ok && r.config.technique != Technique::six_pass && !sc.has_point_light())
    s = {false,
         "the scene has no point light, so no cube: its spot/directional lights render one 2D map each "
         "(measured by six_pass); the single-pass techniques apply to cube maps"};
  if (!s.ok) {
    r.add({Status::unsupported, "support", s.reason, {}});
    return false;
  }
  if (!options_.memory_precheck) return true;
  const MemoryNeed need = estimate_case_memory(r.config, cube_read_back_for(r.config));
  MemoryAvailable available = host_memory_available();
  available.device_budget = options_.memory_budget;
  std::string shortfall = memory_shortfall(need, available, b.device());
  if (shortfall.empty()) return true;
  r.add({Status::resource_error,
         "memory",
         shortfall,
         {{"device_bytes", double(need.device_bytes)}, {"host_bytes", double(need.host_bytes)}}});
  return false;
}

// The shadow plan's figures at the check frame (faces with no caster, object x face draws, over every light)
// and the work counters.
// by_coverage: the atlas the case allocated within its budget (an allocation that exceeds it fails), and each
// light's coverage for results.json.
static void check_shadow_budget(CaseResult& r, const scene::Scene& sc, int check_frame) {
  const int planned = atlas::planned_frame(r.config, check_frame);  // the coverage the tiles were sized by
  for (int k = 0; k < r.config.light_count; ++k)
    r.atlas_coverage.push_back(atlas::screen_coverage(sc, k, r.config.width, r.config.height, planned));
  const uint64_t texels = uint64_t(r.atlas->width) * uint64_t(r.atlas->height);
  const uint64_t budget = atlas::budget_texels(r.config);
  if (texels <= budget) return;
  r.add(
      {Status::failed_check,
       "shadow_budget",
       "the atlas takes " + std::to_string(texels) + " texels, above its budget of " + std::to_string(budget),
       {{"texels", double(texels)}, {"budget", double(budget)}}});
}

// The faces the counted frame drew (their content is that frame's), their texels (at its tiles: `tiles`,
// layout atlas) and the passes that drew them.
static void count_rendered(CaseResult& r, const std::vector<std::array<int, 6>>& face_frames, int frame,
                           const std::optional<atlas::Plan>& tiles) {
  if (face_frames.empty()) return;
  r.faces_rendered = r.passes_rendered = 0;
  r.texels_rendered = 0;
  for (size_t k = 0; k < face_frames.size(); ++k) {
    const int64_t size = tiles ? tiles->lights.at(k).face_size : r.config.cube_size;
    const int faces = int(std::count(face_frames[k].begin(), face_frames[k].end(), frame));
    r.faces_rendered += faces;
    r.texels_rendered += faces * size * size;
    r.passes_rendered += traits(r.config.technique).passes == cube::kFaceCount ? faces : faces > 0;
  }
}

std::vector<PlannedLight> Harness::count_work(CaseResult& r, Backend& b, float light_far) {
  std::vector<PlannedLight> planned;
  // Summed over the case's lights, each planned as the backend plans it (its far: light 0's as read back, the
  // others' their own or fitted as make_frame_uniforms fits them).
  scene::Scene& sc = const_cast<scene::Scene&>(scene_of(r.config));  // not a const object: focus only
  r.shadow_texels = shadow_texels(r.config, &sc);
  r.shadow_storage_bytes = shadow_storage_bytes(r.config, &sc);
  // Layout atlas: the tiles in force at the check frame (frame 0's unless re-planned), in the atlas as
  // allocated.
  if (r.config.layout == Layout::atlas) {
    r.atlas = atlas::plan_at(r.config, sc, options_.check_frame);
    r.atlas_planned_at = atlas::planned_frame(r.config, options_.check_frame);
  }
  if (r.atlas && r.config.atlas_tiles == AtlasTiles::by_coverage)
    check_shadow_budget(r, sc, options_.check_frame);
  for (int k = 0; k < (sc.has_point_light() ? r.config.light_count : 1); ++k) {
    scene::FocusLight focus(sc, k);
    const glm::vec3 light = sc.light().path.at(options_.check_frame);
    const float far_plane = k == 0 ? light_far
                            : r.config.optimizations.fit_range
                                ? cube::fitted_far(sc, light, sc.light().near_plane, sc.light().far_plane)
                                : sc.light().far_plane;
    cube::ShadowDrawPlan plan = cube::plan_shadow_draws(sc, light, sc.light().near_plane, far_plane,
                                                        r.config.optimizations.face_culling);
    const int face_size = r.atlas ? r.atlas->lights.at(size_t(k)).face_size : r.config.cube_size;
    const uint8_t faces = gpu::view_faces(sc, r.config, options_.check_frame, far_plane, face_size);
    cube::keep_faces(plan, faces);
    planned.push_back({k, light, far_plane, faces, face_size});
    r.view_culled_lights += faces == 0;
    r.view_culled_faces += faces == 0 ? 0 : 6 - std::popcount(faces);
    r.empty_faces += plan.empty_faces;
    for (const auto& list : plan.face_objects) r.object_face_pairs += static_cast<int>(list.size());
  }
  // With static caching or an update budget the work of a frame depends on the one before: count the frame
  // after the check frame, rendered right after it (the steady state: zero shadow work while the light stands
  // still, the budget's faces while lights move).
  const bool after_check = r.config.optimizations.static_cache || r.config.update_budget_faces > 0;
  const int counted = options_.check_frame + (after_check ? 1 : 0);
  r.counters = b.count_work(counted);
  const int counted_plan = atlas::planned_frame(r.config, counted);
  const bool replanned = r.atlas && counted_plan != r.atlas_planned_at;
  // The counted frame's tiles: one step on from the check frame's plan, not the chain walked again from frame
  // 0.
  count_rendered(
      r, b.face_frames(), counted,
      replanned ? atlas::plan_after(r.config, sc, counted_plan, *r.atlas, r.atlas_planned_at) : r.atlas);
  return planned;
}

// What a case's floor depends on: backend, scene, cube, frame size, storage, depth format and light count.
// Not the filter, remedies or PCF scale (the floor's lighting has no lookup), nor the optimisations (no
// draws).
static std::string floor_key(const CaseConfig& c) {
  return c.backend + "/" + scene_key(c) + "/c" + std::to_string(c.cube_size) + "/f" +
         std::to_string(c.width) + "x" + std::to_string(c.height) + "/" +
         std::string(to_string(c.technique)) + "/" + std::string(to_string(c.storage)) + "/" +
         std::string(to_string(c.depth_format)) + "/l" + std::to_string(c.light_count) + "/" +
         std::string(to_string(c.light_grouping)) +
         (c.atlas_tiles == AtlasTiles::uniform ? "" : "/tiles_" + std::string(to_string(c.atlas_tiles)));
}

void Harness::measure_floor(CaseResult& r, Backend& b) {
  const std::string key = floor_key(r.config);
  auto it = floors_.find(key);
  if (it == floors_.end()) {
    std::vector<FrameTiming> frames;
    for (int i = 0; i < 2 + kFloorFrames; ++i) {  // two warm-up frames first
      FrameTiming t = b.render(options_.check_frame, FrameKind::floor);
      apply_scripted_clock(options_.inject_frame_ms, 0, t);  // a floor frame has no injected work
      if (i >= 2) frames.push_back(t);
    }
    auto median_of = [&](auto get) {
      std::vector<double> v;
      for (const FrameTiming& f : frames) v.push_back(get(f));
      return summarize(v).median;
    };
    FrameTiming floor;
    floor.shadow.cpu_wall_ms = median_of([](const FrameTiming& f) { return f.shadow.cpu_wall_ms; });
    floor.lighting.cpu_wall_ms = median_of([](const FrameTiming& f) { return f.lighting.cpu_wall_ms; });
    floor.shadow.gpu_ms = median_of([](const FrameTiming& f) { return f.shadow.gpu_ms; });
    floor.lighting.gpu_ms = median_of([](const FrameTiming& f) { return f.lighting.gpu_ms; });
    floor.frame_wall_ms = median_of([](const FrameTiming& f) { return f.frame_wall_ms; });
    it = floors_.emplace(key, floor).first;
  }
  r.floor = it->second;
}

// The cold frame's index: the check frame's, except that in a scene with moving casters a static cache's cold
// frame is the next one, so that the check frame reuses what the dirty rule lets it keep of a frame whose
// casters stood elsewhere (and the images show any face it kept wrongly).
int Harness::cold_frame(const CaseConfig& c) {
  const bool moved = c.optimizations.static_cache && scene_of(c).has_moving_objects();
  return options_.check_frame + (moved ? 1 : 0);
}

// A capture run under RenderDoc (run --capture, bench/cli/capture.h) captures this frame.
void Harness::render_check_frame(const CaseConfig& c, Backend& b) {
  inject_fault(options_, c.id(), false);
  renderdoc::start_frame();
  b.render(options_.check_frame, FrameKind::check);
  if (renderdoc::end_frame()) b.discard_tool_errors();
}

void Harness::prepare(CaseResult& r) {
  // Where the untimed part's time goes, per step (results.json "untimed_ms", the summary's totals).
  auto step = [&r, this](const char* name, auto&& body) {
    send_progress(options_.progress_fd, std::string("step ") + name);
    const auto start = std::chrono::steady_clock::now();
    body();
    r.untimed_ms[name] +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };
  try {
    posed(r.config, options_.check_frame);  // the checks' truths and plans are the check frame's
    Backend& b = backend(r.config.backend);
    if (!admit(r, b)) return;
    step("configure", [&] { activate(r.config); });
    // Cold: right after configure, nothing cached; the timed kind, what the timed frames render.
    step("first_frame", [&] { r.first_frame = b.render(cold_frame(r.config), FrameKind::timed); });
    // The check frame renders every buffer the checks read, and the timed variant's colour beside them. With
    // static caching it is served from the cube the cold frame rendered, so the cache is what gets checked.
    step("check_frame", [&] { render_check_frame(r.config, b); });
    Images images;
    step("read_back", [&] { images = read_light(b, r.config, 0); });
    r.cube_read_back = images.has_full_cube() ? "full" : "sampled";
    r.light_far = images.light_far;
    check_timed_variant(r, images, check_context(r));
    // A many-light case: the other lights the checks read, while the check frame is the last one rendered.
    std::vector<std::pair<int, Images>> others;
    r.light_stride = checked_light_stride(r.config.light_count);
    step("read_back", [&] {
      for (int k : lights_to_check(r.config))
        if (k > 0) others.emplace_back(k, read_light(b, r.config, k));
    });
    if (options_.stability) measure_flicker(r, b, images);
    std::vector<PlannedLight> planned;
    step("work_counters", [&] { planned = count_work(r, b, images.light_far); });
    if (std::vector<std::string> errors = b.drain_api_errors(); !errors.empty()) {
      r.add({Status::failed,
             "api",
             "API error (checking mode): " + std::to_string(errors.size()) +
                 " message(s): " + one_line_log(errors),
             {{"api_errors", double(errors.size())}}});
      return;
    }
    step("floor", [&] { measure_floor(r, b); });
    const bool is_reference = r.config == reference_config(r.config);
    if (is_reference) references_.clear();
    check_lights(r, images, others, is_reference);
    const scene::Camera camera = scene_of(r.config).camera.at(options_.check_frame);
    check_view_culling(r, images, planned, camera.position);
    check_light_clusters(r, images, planned, camera);
    step("staleness", [&] { measure_staleness(r, b); });
    // Last, when the case's status is known: a failed check also keeps every float buffer.
    if (options_.write_images()) step("images", [&] { write_images(r, images); });
    if (is_reference) {
      reference_key_ = group_key(r.config);
      references_[0] = std::move(images);
      for (auto& [k, light_images] : others) references_[k] = std::move(light_images);
    }
  } catch (const std::bad_alloc&) {
    // Host allocation failed (a read-back copy, or a CPU driver's texture): the case fails, the run goes on.
    reference_key_.clear();
    references_.clear();
    MemoryNeed need = estimate_case_memory(r.config, cube_read_back_for(r.config));
    r.add({Status::resource_error,
           "memory",
           "out of host memory (std::bad_alloc): the case needs about " + format_bytes(need.device_bytes) +
               " of targets and " + format_bytes(need.host_bytes) + " of read-back copies",
           {{"device_bytes", double(need.device_bytes)}, {"host_bytes", double(need.host_bytes)}}});
  } catch (const std::exception& e) {
    // Out of device memory is reported by the backends as an error naming it (GL_OUT_OF_MEMORY,
    // VK_ERROR_OUT_OF_DEVICE_MEMORY): a resource error, not a failure of the technique.
    const std::string what = e.what();
    const bool memory = what.find("OUT_OF_MEMORY") != std::string::npos ||
                        what.find("OUT_OF_DEVICE_MEMORY") != std::string::npos ||
                        what.find("OUT_OF_HOST_MEMORY") != std::string::npos;
    r.add({memory ? Status::resource_error : Status::failed, memory ? "memory" : "error", what, {}});
  }
}

}  // namespace omnishadow::bench
