#include "bench/run/case_runner.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

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
#include "bench/truth/truth_cache.h"

namespace omnishadow::bench {

namespace fs = std::filesystem;

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
static void check_shadow_budget(CaseResult& r, const scene::Scene& sc) {
  for (int k = 0; k < r.config.light_count; ++k)
    r.atlas_coverage.push_back(atlas::screen_coverage(sc, k, r.config.width, r.config.height));
  const uint64_t texels = uint64_t(r.atlas->width) * uint64_t(r.atlas->height);
  const uint64_t budget = atlas::budget_texels(r.config);
  if (texels <= budget) return;
  r.add(
      {Status::failed_check,
       "shadow_budget",
       "the atlas takes " + std::to_string(texels) + " texels, above its budget of " + std::to_string(budget),
       {{"texels", double(texels)}, {"budget", double(budget)}}});
}

// The faces the counted frame drew (their content is that frame's), their texels and the passes that drew
// them.
static void count_rendered(CaseResult& r, const std::vector<std::array<int, 6>>& face_frames, int frame) {
  if (face_frames.empty()) return;
  r.faces_rendered = r.passes_rendered = 0;
  r.texels_rendered = 0;
  for (size_t k = 0; k < face_frames.size(); ++k) {
    const int64_t size = r.atlas ? r.atlas->lights.at(k).face_size : r.config.cube_size;
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
  if (r.config.layout == Layout::atlas) r.atlas = atlas::plan_for(r.config, sc);
  if (r.atlas && r.config.atlas_tiles == AtlasTiles::by_coverage) check_shadow_budget(r, sc);
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
  count_rendered(r, b.face_frames(), counted);
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
    check_view_culling(r, images, planned, scene_of(r.config).camera.position);
    check_light_clusters(r, images, planned, scene_of(r.config).camera);
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

CheckContext Harness::check_context(const CaseResult& r) {
  CheckContext ctx{scene_of(r.config), backend(r.config.backend).device(), options_, {}};
  if (options_.write_images())
    ctx.write_image = [this, &r](const std::string& rel, int width, int height, std::vector<uint8_t> rgb) {
      const fs::path path = fs::path(options_.out_dir) / rel;
      fs::create_directories(path.parent_path());
      write_later(r, [path = path.string(), width, height, rgb = std::move(rgb)] {
        write_png_rgb_top_down(path, width, height, rgb);
      });
    };
  return ctx;
}

// Every checked light's checks, the first's into the case itself and each other's on its own (joined under
// its name, merge_light_findings); with several, the case's accuracy pools them.
void Harness::check_lights(CaseResult& r, Images& images, std::vector<std::pair<int, Images>>& others,
                           bool is_reference) {
  check_light(r, images, 0, is_reference);
  for (auto& [k, light_images] : others) {
    CaseResult light_result;
    light_result.config = r.config;
    check_light(light_result, light_images, k, is_reference);
    r.non_finite_cube += light_result.non_finite_cube;
    r.non_finite_shadow += light_result.non_finite_shadow;
    for (const auto& [name, ms] : light_result.untimed_ms) r.untimed_ms[name] += ms;
    merge_light_findings(r, k, std::move(light_result));
  }
  if (others.empty()) return;
  r.per_light.insert(r.per_light.begin(), LightReport{0, r.accuracy, r.cube_texels, r.lookups});
  r.accuracy = pooled_accuracy(r.per_light);
  if (!options_.accuracy || r.light_stride != 1) return;
  // Every light checked: their shadows together in the lit frame (the truths are the cached ones just used).
  scene::Scene& sc = const_cast<scene::Scene&>(scene_of(r.config));  // not a const object: focus only
  std::vector<std::pair<const Truth*, const Images*>> lights;
  for (int k = 0; k <= int(others.size()); ++k) {
    scene::FocusLight focus(sc, k);
    const Images& light_images = k == 0 ? images : others[size_t(k - 1)].second;
    lights.emplace_back(&truths_.truth(r.config, sc, options_.check_frame, light_images, options_.truth),
                        &light_images);
  }
  r.lit_psnr_every_light_db = lit_psnr_of_lights(lights);
}

// Light `light`'s checks: non-finite values, its map against exact first hits, its shadow against exact
// visibility, its lookups replayed, and its images against six_pass's and the other API's. The scene's focus
// is on the light meanwhile, so that every check (written for one light) reads it. Images of lights other
// than the first are not written, nor heat maps made of them.
void Harness::check_light(CaseResult& r, Images& images, int light, bool is_reference) {
  // The library's scenes are not const objects; the focus is put back when the guard goes.
  scene::FocusLight focus(const_cast<scene::Scene&>(scene_of(r.config)), light);
  auto step = [&r](const char* name, auto&& body) {
    const auto start = std::chrono::steady_clock::now();
    body();
    r.untimed_ms[name] +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };
  count_non_finite(r, images);
  CheckContext checks = check_context(r);
  if (light > 0) checks.write_image = {};
  if (options_.accuracy) {
    step("cube_and_map_truth", [&] {
      check_cube(r, images, checks, truths_);
      check_moment_cube(r, images);
      if (light == 0) check_maps(r, images, checks, truths_);
    });
    step("accuracy", [&] { check_accuracy(r, images, checks, truths_); });
  }
  step("lookups", [&] { check_lookups_of(r, images, checks); });
  step("comparisons", [&] {
    if (!is_reference) check_against_six_pass(r, images, light);
    check_against_other_backend(r, images, light);
  });
}

std::vector<int> Harness::lights_to_check(const CaseConfig& c) {
  std::vector<int> lights = checked_lights(c.light_count);
  const scene::Scene& s = scene_of(c);
  if (c.light_count <= kCheckedLights || int(s.point_lights.size()) < c.light_count) return lights;
  int farthest = 0;
  double most = -1.0;
  for (int k = 0; k < c.light_count; ++k) {
    const double ratio = atlas::distance_over_range(s, k);
    if (ratio > most) most = ratio, farthest = k;
  }
  if (std::find(lights.begin(), lights.end(), farthest) == lights.end()) lights.push_back(farthest);
  return lights;
}

// The six_pass rendering of the case's group (rendered now if six_pass is not in the matrix or ran in another
// shard), and both cubes read in full when their face hashes differ, for the checks to compare.
void Harness::check_against_six_pass(CaseResult& r, Images& images, int light) {
  CaseConfig ref_config = reference_config(r.config);
  if (reference_key_ != group_key(r.config)) references_.clear();
  if (!references_.count(light)) {  // every checked light's at once: one check frame
    Backend& b = activate(ref_config);
    b.render(options_.check_frame, FrameKind::check);
    for (int k : lights_to_check(ref_config)) references_[k] = read_light(b, ref_config, k);
    reference_key_ = group_key(r.config);
    activate(r.config);  // leave the backend on the case being measured
  }
  Images& reference = references_.at(light);
  if (!cubes_equal_by_hash(images, reference)) {
    if (!images.has_full_cube()) {
      read_full_cube(r.config, images, light);
      r.cube_read_back = "sampled+full";
    }
    if (!reference.has_full_cube()) {
      read_full_cube(ref_config, reference, light);
      activate(r.config);
    }
  }
  check_against_reference(r, images, reference, check_context(r));
}

// The first API to render a case keeps its images; the same case on another API is held to them.
void Harness::check_against_other_backend(CaseResult& r, const Images& images, int light) {
  std::string id = r.config.id();
  std::string key = id.substr(id.find('/')) + (light > 0 ? "#l" + std::to_string(light) : "");
  auto it = cross_.find(key);
  if (it == cross_.end()) {
    cross_[key] = {id, images.lit_rgba8, images.shadow_factor};
    return;
  }
  const CrossReference& ref = it->second;
  if (ref.case_id.substr(0, ref.case_id.find('/')) == r.config.backend) return;
  check_against_other_api(r, images, ref, check_context(r));
}

void Harness::count_non_finite(CaseResult& r, const Images& images) {
  auto count = [](const std::vector<float>& v) {
    return static_cast<uint64_t>(
        std::count_if(v.begin(), v.end(), [](float x) { return !std::isfinite(x); }));
  };
  for (const CubeFaceSummary& face : images.cube_summary) r.non_finite_cube += face.non_finite;
  r.non_finite_shadow = count(images.shadow_factor);
  r.non_finite_position = count(images.world_position);
  if (r.non_finite_cube + r.non_finite_shadow + r.non_finite_position > 0) {
    r.add({Status::failed_check,
           "non_finite",
           "non-finite values read back: " + std::to_string(r.non_finite_cube) + " in the cube, " +
               std::to_string(r.non_finite_shadow) + " in the shadow factor, " +
               std::to_string(r.non_finite_position) + " in world positions",
           {{"cube", double(r.non_finite_cube)},
            {"shadow_factor", double(r.non_finite_shadow)},
            {"world_position", double(r.non_finite_position)}}});
  }
}

// The next frame, compared with this one: on a light that moves by tiny steps, the shadow should barely move.
// Leaves the backend on the case (the next read_back is check_frame + 1's; the caller holds its images).
void Harness::measure_flicker(CaseResult& r, Backend& b, const Images& images) {
  b.render(options_.check_frame + 1, FrameKind::check);
  Images next = b.read_back(CubeReadBack::sampled);
  uint64_t flipped = 0, covered = 0;
  double sum = 0.0;
  for (size_t i = 0; i < images.shadow_factor.size() && i < next.shadow_factor.size(); ++i) {
    if (images.world_position[4 * i + 3] != 1.0f) continue;
    ++covered;
    double d = std::fabs(double(next.shadow_factor[i]) - double(images.shadow_factor[i]));
    sum += d;
    flipped += d > 0.5;
  }
  r.flicker_percent = covered ? 100.0 * double(flipped) / double(covered) : 0.0;
  r.flicker_mean_abs = covered ? sum / double(covered) : 0.0;
}

// The case's image files (--images): the lit frame and shadow factor as PNG, and the float buffers as PFM
// (every case with --images all, failing cases with failed), encoded on the writer thread where there is one.
void Harness::write_images(CaseResult& r, const Images& img) {
  fs::path rel = fs::path("images") / r.config.id();
  fs::path dir = fs::path(options_.out_dir) / rel;
  fs::create_directories(dir);
  auto out = [&](const std::string& role, const std::string& file) {
    r.images[role] = (rel / file).string();
    return (dir / file).string();
  };
  const bool failed = r.status == Status::failed_check || r.status == Status::failed_quality;
  // The float buffers (24 bytes a pixel, 1.9 MB per 800x600 buffer) are what a failed check needs to be
  // examined.
  const bool floats = options_.images == RunOptions::ImagePolicy::all || failed;
  struct Files {
    std::string lit, shadow_png, cube, shadow_pfm, position, coverage, cube_pfm;
    std::vector<std::string> maps;
  } files{out("lit", "lit.png"), out("shadow_factor_png", "shadow_factor.png"),
          out("cube_faces", "cube_faces.png")};
  if (floats) {
    files.shadow_pfm = out("shadow_factor", "shadow_factor.pfm");
    files.position = out("world_position", "world_position.pfm");
    files.coverage = out("coverage", "coverage.pfm");
    // What the texel truths read, for studying a finding offline: the cube as distances (faces side by side,
    // row t = 0 first, i.e. PFM's bottom row), each 2D map as window depth (row 0 = NDC y = -1, PFM's bottom
    // row).
    if (img.cube_size > 0) files.cube_pfm = out("cube_distance", "cube_distance.pfm");
    for (size_t m = 0; m < img.map_depth.size(); ++m)
      files.maps.push_back(out("map_depth_" + std::to_string(m), "map_" + std::to_string(m) + "_depth.pfm"));
  }
  // The writer gets its own copies: `img` may be reused (the six_pass reference) before the files are
  // written.
  write_later(r, [files, w = img.width, h = img.height, n = face_edge(img), far_plane = img.light_far,
                  lit = img.lit_rgba8, shadow = img.shadow_factor, cube = concat_faces(img),
                  position = floats ? img.world_position : std::vector<float>{}, map_size = img.map_size,
                  maps = floats ? img.map_depth : std::vector<std::vector<float>>{}] {
    write_png_rgba_bottom_up(files.lit, w, h, lit);
    write_png_gray(files.shadow_png, w, h, shadow, 0.0f, 1.0f, true);
    write_png_gray(files.cube, n * 6, n, cube, 0.0f, far_plane, false);
    if (files.shadow_pfm.empty()) return;
    write_pfm(files.shadow_pfm, w, h, 1, shadow);
    std::vector<float> xyz, coverage;
    xyz.reserve(position.size() / 4 * 3);
    coverage.reserve(position.size() / 4);
    for (size_t i = 0; i < position.size(); i += 4) {
      xyz.insert(xyz.end(), position.begin() + static_cast<ptrdiff_t>(i),
                 position.begin() + static_cast<ptrdiff_t>(i) + 3);
      coverage.push_back(position[i + 3]);
    }
    write_pfm(files.position, w, h, 3, xyz);
    write_pfm(files.coverage, w, h, 1, coverage);
    if (!files.cube_pfm.empty()) write_pfm(files.cube_pfm, n * 6, n, 1, cube);
    for (size_t m = 0; m < files.maps.size() && m < maps.size(); ++m)
      write_pfm(files.maps[m], map_size, map_size, 1, maps[m]);
  });
}

}  // namespace omnishadow::bench
