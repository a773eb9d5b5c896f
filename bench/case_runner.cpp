#include "bench/case_runner.h"

#include <algorithm>
#include <chrono>
#include <cfloat>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "backends/common/cube_faces.h"
#include "backends/common/shadow_plan.h"
#include "bench/image_io.h"
#include "bench/memory_budget.h"
#include "bench/timing_stats.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;

// The case id with the technique removed: every technique of one group shares the six_pass reference.
// The case every other case of its group is checked against: six_pass without culling or caching (which must
// not change a single value). fit_range stays: it changes the stored depth's scale, so it has its own reference.
CaseConfig reference_config(const CaseConfig& c) {
  CaseConfig k = c;
  k.technique = Technique::six_pass;
  k.optimizations.face_culling = false;
  k.optimizations.static_cache = false;
  return k;
}

std::string group_key(const CaseConfig& c) { return reference_config(c).id(); }

std::vector<float> concat_faces(const Images& img) {
  // Faces side by side, face order left to right, so one PNG shows the whole cube.
  int n = img.cube_size;
  std::vector<float> strip(static_cast<size_t>(n) * static_cast<size_t>(n) * 6);
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < n; ++y)
      std::copy_n(img.cube_distance[static_cast<size_t>(f)].begin() + static_cast<ptrdiff_t>(y) * n, n,
                  strip.begin() + (static_cast<ptrdiff_t>(y) * 6 + f) * n);
  return strip;
}

std::vector<float> scaled(std::vector<float> v, float scale) {
  for (float& x : v) x = x * scale;
  return v;
}

std::vector<float> luminance(const std::vector<uint8_t>& rgba) {
  std::vector<float> out(rgba.size() / 4);
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = (static_cast<float>(rgba[4 * i]) + rgba[4 * i + 1] + rgba[4 * i + 2]) / (3.0f * 255.0f);
  return out;
}

// Per pixel, the largest channel difference: a single float image that diff_image_rgb can colour.
std::vector<float> max_channel_difference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  std::vector<float> out(a.size() / 4);
  for (size_t i = 0; i < out.size(); ++i) {
    int d = 0;
    for (size_t k = 0; k < 4; ++k) d = std::max(d, std::abs(int(a[4 * i + k]) - int(b[4 * i + k])));
    out[i] = static_cast<float>(d);
  }
  return out;
}

bool all_faces_identical(const Images& img) {
  for (int f = 1; f < 6; ++f)
    if (img.cube_distance[static_cast<size_t>(f)] != img.cube_distance[0]) return false;
  return true;
}

// A face nothing was drawn to still holds the clear value everywhere: far (linear storage) or FLT_MAX (r32f).
std::vector<int> untouched_faces(const Images& img, float far_plane) {
  std::vector<int> out;
  for (int f = 0; f < 6; ++f) {
    const auto& face = img.cube_distance[static_cast<size_t>(f)];
    float first = face.empty() ? 0.0f : face.front();
    bool clear = (first == far_plane || first == FLT_MAX) &&
                 std::all_of(face.begin(), face.end(), [&](float v) { return v == first; });
    if (clear) out.push_back(f);
  }
  return out;
}

// Evidence from the images that the driver, not the technique, went wrong; empty when there is none.
std::string driver_evidence(const Images& img, const Images& ref, float far_plane) {
  if (all_faces_identical(img) && !all_faces_identical(ref))
    return "all six faces hold the same image while six_pass's differ: the driver rendered every layer/view "
           "into one face";
  std::vector<int> mine = untouched_faces(img, far_plane), theirs = untouched_faces(ref, far_plane);
  std::vector<int> lost;
  for (int f : mine)
    if (std::find(theirs.begin(), theirs.end(), f) == theirs.end()) lost.push_back(f);
  if (lost.empty()) return "";
  std::string names;
  for (int f : lost) names += (names.empty() ? "" : " ") + std::string(cube::kFaceNames[static_cast<size_t>(f)]);
  return std::to_string(lost.size()) + " of 6 faces (" + names +
         ") were never written while six_pass wrote them: the driver did not route every layer/view to its face";
}

std::map<std::string, double> check_figures(const CheckResult& c) {
  return {{"percent_differing", c.difference.percent_differing()},
          {"max_abs", c.difference.max_abs},
          {"differing", double(c.difference.differing)}};
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

std::string_view to_string(Status s) {
  switch (s) {
    case Status::ok: return "ok";
    case Status::failed_quality: return "failed_quality";
    case Status::failed_check: return "failed_check";
    case Status::interrupted: return "interrupted";
    case Status::resource_error: return "resource_error";
    case Status::failed: return "failed";
    case Status::unsupported: return "unsupported";
  }
  return "?";
}

bool fails_run(Status s) {
  return s == Status::failed_quality || s == Status::failed_check || s == Status::resource_error ||
         s == Status::failed;
}

void CaseResult::add(Finding finding) {
  if (static_cast<int>(finding.status) > static_cast<int>(status)) status = finding.status;
  reason += (reason.empty() ? "" : "; ") + finding.message;
  findings.push_back(std::move(finding));
}

Harness::Harness(RunOptions options) : options_(std::move(options)) {
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

void Harness::add_backend(const std::string& name, std::unique_ptr<Backend> backend) {
  probes_.erase(name);
  backends_[name] = std::move(backend);
  std::erase(creation_order_, name);
  creation_order_.push_back(name);
  loaded_scene_.erase(name);
}

std::string Harness::scene_path(const std::string& name) const {
  if (name.find('/') != std::string::npos || name.ends_with(".json")) return name;
  return (fs::path(options_.scenes_dir) / (name + ".json")).string();
}

// Scenes are cached per name and load option: the rebased room is another scene.
std::string scene_key(const std::string& name, bool rebase_origin) { return name + (rebase_origin ? "#rebase" : ""); }

const scene::Scene& Harness::scene(const std::string& name, bool rebase_origin) {
  const std::string key = scene_key(name, rebase_origin);
  auto it = scenes_.find(key);
  if (it != scenes_.end()) return it->second;
  scene::LoadOptions load;
  load.rebase_origin = rebase_origin;
  scene::Scene s = scene::load_scene_file(scene_path(name), load);
  s.name = name;
  return scenes_.emplace(key, std::move(s)).first->second;
}

Backend& Harness::activate(const CaseConfig& config) {
  Backend& b = backend(config.backend);
  const std::string key = scene_key(config.scene, config.remedies.rebase_origin);
  if (loaded_scene_[config.backend] != key) {
    loaded_scene_[config.backend].clear();
    b.load(scene_of(config));
    loaded_scene_[config.backend] = key;
  }
  b.configure(config);
  return b;
}

// Whether the case can run here at all: supported by the backend and the scene, and (unless told not to check)
// fitting in memory. Adds the finding that says why not.
bool Harness::admit(CaseResult& r, Backend& b) {
  Support s = b.supports(r.config);
  if (s.ok && r.config.technique != Technique::six_pass && !scene_of(r.config).has_point_light)
    s = {false, "the scene has no point light, so no cube: its spot/directional lights render one 2D map each "
                "(measured by six_pass); the single-pass techniques apply to cube maps"};
  if (!s.ok) {
    r.add({Status::unsupported, "support", s.reason, {}});
    return false;
  }
  if (!options_.memory_precheck) return true;
  const MemoryNeed need = estimate_case_memory(r.config);
  std::string shortfall = memory_shortfall(need, host_memory_available(), b.device());
  if (shortfall.empty()) return true;
  r.add({Status::resource_error, "memory", shortfall,
         {{"device_bytes", double(need.device_bytes)}, {"host_bytes", double(need.host_bytes)}}});
  return false;
}

// The shadow plan's figures at the check frame (faces with no caster, object x face draws) and the work counters.
void Harness::count_work(CaseResult& r, Backend& b, float light_far) {
  const scene::Scene& sc = scene_of(r.config);
  cube::ShadowDrawPlan plan = cube::plan_shadow_draws(sc, sc.light.path.at(options_.check_frame), sc.light.near_plane,
                                                      light_far, r.config.optimizations.face_culling);
  r.empty_faces = plan.empty_faces;
  for (const auto& list : plan.face_objects) r.object_face_pairs += static_cast<int>(list.size());
  // With static caching the work of a frame depends on the one before: count the frame after the check frame,
  // rendered right after it (the steady state: zero shadow work while the light stands still).
  r.counters = b.count_work(options_.check_frame + (r.config.optimizations.static_cache ? 1 : 0));
}

// The cube against exact first-hit distances, whatever the camera sees. Cases of one scene, light, range and size
// share the truth; a scene without a point light has no cube to check.
// Not the filter, remedies or PCF scale (the floor's lighting has no lookup), nor the optimisations (no draws).
static std::string floor_key(const CaseConfig& c) {
  return c.backend + "/" + c.scene + (c.remedies.rebase_origin ? "#rebase" : "") + "/c" + std::to_string(c.cube_size) +
         "/f" + std::to_string(c.width) + "x" + std::to_string(c.height) + "/" + std::string(to_string(c.technique)) +
         "/" + std::string(to_string(c.storage)) + "/" + std::string(to_string(c.depth_format));
}

void Harness::measure_floor(CaseResult& r, Backend& b) {
  const std::string key = floor_key(r.config);
  auto it = floors_.find(key);
  if (it == floors_.end()) {
    std::vector<FrameTiming> frames;
    for (int i = 0; i < 2 + kFloorFrames; ++i) {  // two warm-up frames first
      FrameTiming t = b.render(options_.check_frame, FrameKind::floor);
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

void Harness::prepare(CaseResult& r) {
  // Where the untimed part's time goes, per step (results.json "untimed_ms", the summary's totals).
  auto step = [&r](const char* name, auto&& body) {
    const auto start = std::chrono::steady_clock::now();
    body();
    r.untimed_ms[name] += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };
  try {
    Backend& b = backend(r.config.backend);
    if (!admit(r, b)) return;
    step("configure", [&] { activate(r.config); });
    // Cold: right after configure, nothing cached; the timed kind, what the timed frames render.
    step("first_frame", [&] { r.first_frame = b.render(options_.check_frame, FrameKind::timed); });
    // The check frame renders every buffer the checks read, and the timed variant's colour beside them. With
    // static caching it is served from the cube the cold frame rendered, so the cache is what gets checked.
    step("check_frame", [&] { b.render(options_.check_frame, FrameKind::check); });
    Images images;
    step("read_back", [&] { images = b.read_back(); });
    r.light_far = images.light_far;
    count_non_finite(r, images);
    check_timed_variant(r, images);
    if (options_.stability) measure_flicker(r, b, images);
    step("work_counters", [&] { count_work(r, b, images.light_far); });
    if (std::vector<std::string> errors = b.drain_api_errors(); !errors.empty()) {
      r.add({Status::failed, "api",
             "API error (checking mode): " + errors.front() +
                 (errors.size() > 1 ? " (+" + std::to_string(errors.size() - 1) + " more)" : ""),
             {{"api_errors", double(errors.size())}}});
      return;
    }
    if (options_.accuracy) {
      step("cube_and_map_truth", [&] {
        check_cube(r, images);
        check_maps(r, images);
      });
      step("accuracy", [&] { check_accuracy(r, images); });
    }
    step("floor", [&] { measure_floor(r, b); });
    const bool is_reference = r.config == reference_config(r.config);
    step("comparisons", [&] {
      if (!is_reference) check_against_six_pass(r, images);
      check_against_other_backend(r, images);
    });
    // Last, when the case's status is known: a failed check also keeps every float buffer.
    if (options_.write_images()) step("images", [&] { write_images(r, images); });
    if (is_reference) {
      reference_key_ = group_key(r.config);
      reference_ = std::move(images);
    }
  } catch (const std::bad_alloc&) {
    // Host allocation failed (a read-back copy, or a CPU driver's texture): the case fails, the run goes on.
    reference_key_.clear();
    reference_ = Images{};
    MemoryNeed need = estimate_case_memory(r.config);
    r.add({Status::resource_error, "memory",
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

void Harness::count_non_finite(CaseResult& r, const Images& images) {
  auto count = [](const std::vector<float>& v) {
    return static_cast<uint64_t>(std::count_if(v.begin(), v.end(), [](float x) { return !std::isfinite(x); }));
  };
  for (const auto& face : images.cube_distance) r.non_finite_cube += count(face);
  r.non_finite_shadow = count(images.shadow_factor);
  r.non_finite_position = count(images.world_position);
  if (r.non_finite_cube + r.non_finite_shadow + r.non_finite_position > 0) {
    r.add({Status::failed_check, "non_finite",
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
  Images next = b.read_back();
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

// What was timed is what was checked: the timed lighting variant's colour must equal the check variant's, bit for
// bit (they share every line that computes it; only the check variant's extra outputs differ).
void Harness::check_timed_variant(CaseResult& r, const Images& images) {
  CheckResult check{"timed_lit", r.config.id() + " (check variant)"};
  check.difference = compare_values(images.timed_lit_rgba8, images.lit_rgba8, 0.0);
  std::vector<float> diff = max_channel_difference(images.timed_lit_rgba8, images.lit_rgba8);
  record_check(r, check, diff, std::vector<float>(diff.size(), 0.0f), luminance(images.lit_rgba8), images.width,
               images.height, 64.0, true);
  if (!r.checks.back().passed)
    r.add({Status::failed_check, "timed_lit",
           "timed_lit: the timed lighting variant's colour differs from the check variant's in " +
               fmt(check.difference.percent_differing()) + "% of values (max abs " + fmt(check.difference.max_abs) +
               "): the timed frame does not render what was checked",
           check_figures(check)});
}

void Harness::check_against_six_pass(CaseResult& r, const Images& images) {
  CaseConfig ref_config = reference_config(r.config);
  if (reference_key_ != group_key(r.config)) {
    // six_pass is not in the matrix (or ran in another shard): render it now, untimed.
    Backend& b = activate(ref_config);
    b.render(options_.check_frame, FrameKind::check);
    reference_ = b.read_back();
    reference_key_ = group_key(r.config);
    activate(r.config);  // leave the backend on the case being measured
  }
  const Images& ref = *reference_;
  const float far_plane = ref.light_far;

  // Cube faces, in world units: the technique must store what six_pass stores.
  std::vector<float> faces = concat_faces(images), ref_faces = concat_faces(ref);
  CheckResult faces_check{"cube_faces", ref_config.id()};
  faces_check.tolerance = options_.face_tolerance;
  faces_check.difference = compare_values(faces, ref_faces, options_.face_tolerance);
  record_check(r, faces_check, faces, ref_faces, scaled(ref_faces, 1.0f / far_plane), images.cube_size * 6, images.cube_size,
         far_plane * 0.05, false);

  CheckResult shadow_check{"shadow_factor", ref_config.id()};
  shadow_check.tolerance = 0.0;
  shadow_check.difference = compare_values(images.shadow_factor, ref.shadow_factor, 0.0);
  record_check(r, shadow_check, images.shadow_factor, ref.shadow_factor, ref.shadow_factor, images.width, images.height, 1.0,
         true);

  CheckResult lit_check{"lit", ref_config.id()};
  lit_check.tolerance = options_.lit_tolerance;
  lit_check.difference = compare_values(images.lit_rgba8, ref.lit_rgba8, options_.lit_tolerance);
  std::vector<float> lit_diff = max_channel_difference(images.lit_rgba8, ref.lit_rgba8);
  record_check(r, lit_check, lit_diff, std::vector<float>(lit_diff.size(), 0.0f), luminance(ref.lit_rgba8), images.width,
         images.height, 64.0, true);

  bool failed = false;
  for (const CheckResult& c : r.checks)
    if (!c.passed && (c.name == "cube_faces" || c.name == "shadow_factor" || c.name == "lit")) {
      failed = true;
      r.add({Status::failed_check, c.name,
             c.name + " differ from " + c.against + " in " + fmt(c.difference.percent_differing()) +
                 "% of values (max abs " + fmt(c.difference.max_abs) + ")",
             check_figures(c)});
    }
  if (failed)
    if (std::string evidence = driver_evidence(images, ref, far_plane); !evidence.empty())
      r.add({Status::failed_check, "driver_evidence", evidence, {}});
}

void Harness::record_check(CaseResult& r, CheckResult c, const std::vector<float>& a, const std::vector<float>& b,
                           const std::vector<float>& grey, int width, int height, double scale, bool flip) {
  c.passed = c.max_percent > 0 ? c.difference.percent_differing() <= c.max_percent : c.difference.differing == 0;
  if (!c.passed && options_.write_images()) {
    fs::path dir = fs::path("images") / r.config.id();
    c.diff_image = (dir / ("diff_" + c.name + ".png")).string();
    fs::create_directories(fs::path(options_.out_dir) / dir);
    write_later(r, [path = (fs::path(options_.out_dir) / c.diff_image).string(), width, height,
                    rgb = diff_image_rgb(a, b, grey, width, height, c.tolerance, scale, flip)] {
      write_png_rgb_top_down(path, width, height, rgb);
    });
  }
  r.checks.push_back(c);
}

void Harness::check_against_other_backend(CaseResult& r, const Images& images) {
  std::string id = r.config.id();
  std::string key = id.substr(id.find('/'));
  auto it = cross_.find(key);
  if (it == cross_.end()) {
    cross_[key] = {id, images.lit_rgba8, images.shadow_factor};
    return;
  }
  const CrossReference& ref = it->second;
  if (ref.case_id.substr(0, ref.case_id.find('/')) == r.config.backend) return;

  CheckResult shadow{"cross_backend_shadow_factor", ref.case_id};
  shadow.tolerance = options_.cross_shadow_tolerance;
  shadow.max_percent = options_.cross_max_percent;
  shadow.difference = compare_values(images.shadow_factor, ref.shadow_factor, options_.cross_shadow_tolerance);
  record_check(r, shadow, images.shadow_factor, ref.shadow_factor, ref.shadow_factor, images.width, images.height,
               1.0, true);
  CheckResult lit{"cross_backend_lit", ref.case_id};
  lit.tolerance = options_.cross_lit_tolerance;
  lit.max_percent = options_.cross_max_percent;
  lit.difference = compare_values(images.lit_rgba8, ref.lit, options_.cross_lit_tolerance);
  std::vector<float> lit_diff = max_channel_difference(images.lit_rgba8, ref.lit);
  record_check(r, lit, lit_diff, std::vector<float>(lit_diff.size(), 0.0f), luminance(ref.lit), images.width,
               images.height, 64.0, true);
  for (const CheckResult* c : {&r.checks[r.checks.size() - 2], &r.checks.back()})
    if (!c->passed)
      r.add({Status::failed_check, c->name,
             c->name + ": " + fmt(c->difference.percent_differing()) + "% of values differ from " + c->against +
                 " (allowed " + fmt(c->max_percent) + "%)",
             check_figures(*c)});
}

void Harness::write_images(CaseResult& r, const Images& img) {
  fs::path rel = fs::path("images") / r.config.id();
  fs::path dir = fs::path(options_.out_dir) / rel;
  fs::create_directories(dir);
  auto out = [&](const std::string& role, const std::string& file) {
    r.images[role] = (rel / file).string();
    return (dir / file).string();
  };
  const bool failed = r.status == Status::failed_check || r.status == Status::failed_quality;
  // The float buffers (24 bytes a pixel, 1.9 MB per 800x600 buffer) are what a failed check needs to be examined.
  const bool floats = options_.images == RunOptions::ImagePolicy::all || failed;
  struct Files {
    std::string lit, shadow_png, cube, shadow_pfm, position, coverage;
  } files{out("lit", "lit.png"), out("shadow_factor_png", "shadow_factor.png"), out("cube_faces", "cube_faces.png")};
  if (floats) {
    files.shadow_pfm = out("shadow_factor", "shadow_factor.pfm");
    files.position = out("world_position", "world_position.pfm");
    files.coverage = out("coverage", "coverage.pfm");
  }
  // The writer gets its own copies: `img` may be reused (the six_pass reference) before the files are written.
  write_later(r, [files, w = img.width, h = img.height, n = img.cube_size, far_plane = img.light_far,
                  lit = img.lit_rgba8, shadow = img.shadow_factor, cube = concat_faces(img),
                  position = floats ? img.world_position : std::vector<float>{}] {
    write_png_rgba_bottom_up(files.lit, w, h, lit);
    write_png_gray(files.shadow_png, w, h, shadow, 0.0f, 1.0f, true);
    write_png_gray(files.cube, n * 6, n, cube, 0.0f, far_plane, false);
    if (files.shadow_pfm.empty()) return;
    write_pfm(files.shadow_pfm, w, h, 1, shadow);
    std::vector<float> xyz, coverage;
    xyz.reserve(position.size() / 4 * 3);
    coverage.reserve(position.size() / 4);
    for (size_t i = 0; i < position.size(); i += 4) {
      xyz.insert(xyz.end(), position.begin() + static_cast<ptrdiff_t>(i), position.begin() + static_cast<ptrdiff_t>(i) + 3);
      coverage.push_back(position[i + 3]);
    }
    write_pfm(files.position, w, h, 3, xyz);
    write_pfm(files.coverage, w, h, 1, coverage);
  });
}

}  // namespace omnishadow::bench
