// A case's check steps, after its check frame: each checked light held to the truths, to six_pass and to the
// other backend; non-finite texels counted, flicker measured, the images written.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "bench/io/image_io.h"
#include "bench/run/case_runner.h"
#include "bench/truth/truth_cache.h"

namespace omnishadow::bench {

namespace fs = std::filesystem;

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
  if (light == 0) step("camera", [&] { check_camera(r, images, checks); });  // every light's positions alike
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
  // Where the technique's coverage may flip at triangle edges, the texels that differ are judged by the
  // light's cube truth, computed on first use: a cube that differs nowhere needs none.
  const scene::Scene& sc = scene_of(r.config);
  const CubeTruth* truth = nullptr;
  const int subpixel_bits = backend(r.config.backend).device().subpixel_bits;
  const TexelAdmissible admissible = [&](int layer, int s, int t, double distance) {
    if (!truth)
      truth = &truths_.cube_truth(r.config, sc, sc.light().path.at(options_.check_frame),
                                  sc.light().near_plane, images.light_far, images.cube_size);
    return texel_admissible(*truth, r.config.storage, r.config.depth_format, sc.light().near_plane,
                            images.light_far, subpixel_bits, layer, s, t, distance);
  };
  check_against_reference(r, images, reference, check_context(r), admissible);
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
