// The Harness's truth checks: the cube's and the 2D maps' texels against exact ray casts, and each case's
// shadow against exact visibility (with the --max-error limits and the error heatmap). The ray caster and the
// truths are cached per loaded scene (and frame, light and sizes): every case of a group shares them.

#include <cstdio>
#include <filesystem>

#include "bench/results/image_io.h"
#include "bench/run/case_runner.h"

namespace omnishadow::bench {

namespace fs = std::filesystem;

namespace {

// A cube or map whose checked texels are wrong beyond `limit_percent` fails its case. One texel alone can be
// a tie at an edge through its centre (a 2-texel cube has 24 texels in all), so it takes more than one.
template <typename Report>
void add_texel_finding(CaseResult& r, const char* check, const Report& report, double limit_percent) {
  if (report.bad_percent() <= limit_percent || report.bad() <= 1) return;
  r.add({Status::failed_check,
         check,
         describe(report),
         {{"bad_percent", report.bad_percent()},
          {"max_error", report.max_error},
          {"texels", double(report.texels)}}});
}

}  // namespace

void Harness::check_cube(CaseResult& r, const Images& images) {
  const scene::Scene& sc = scene_of(r.config);
  if (!sc.has_point_light || images.cube_size < 1) return;
  const glm::vec3 light = sc.light.path.at(options_.check_frame);
  char key[256];
  const TexelMap map = traits(r.config.layout).texel_map;
  std::snprintf(key, sizeof key, "%s/%.9g,%.9g,%.9g/%.9g/%.9g/%d/%d/%d", scene_key(r.config).c_str(), light.x,
                light.y, light.z, sc.light.near_plane, images.light_far, images.cube_size,
                int(r.config.remedies.two_sided), int(map));
  auto it = cube_truths_.find(key);
  if (it == cube_truths_.end()) {
    it = cube_truths_
             .emplace(key, compute_cube_truth(caster_of(r.config), sc, light, sc.light.near_plane,
                                              images.light_far, images.cube_size, r.config.remedies.two_sided,
                                              map))
             .first;
  }
  r.cube_texels = check_cube_texels(it->second, images, r.config.storage, r.config.depth_format,
                                    sc.light.near_plane, backend(r.config.backend).device().subpixel_bits);
  // A paraboloid's rasterised triangles have straight edges where the exact map draws curves: its texels
  // differ from the exact ones by the layout's own error, which depends on tessellation. That is a figure
  // (results.json cube_texels), not a failed check; its technique checks (equal to six_pass) and exact
  // visibility still judge.
  if (map == TexelMap::paraboloid) return;
  add_texel_finding(r, "cube_texels", *r.cube_texels, kCubeTexelLimitPercent);
}

// Not a texel limit: the bound is rounding only, so one moment outside it is a device storing other moments.
void Harness::check_moment_cube(CaseResult& r, const Images& images) {
  if (traits(r.config.storage).moments == MomentKind::none || images.moments[0].empty()) return;
  r.moments = check_moments(images, r.config.storage, r.config.depth_format, r.config.moments);
  if (r.moments->ok()) return;
  r.add({Status::failed_check,
         "moments",
         describe(*r.moments),
         {{"outside", double(r.moments->outside)},
          {"non_finite", double(r.moments->non_finite)},
          {"values", double(r.moments->values)}}});
}

void Harness::check_maps(CaseResult& r, const Images& images) {
  const scene::Scene& sc = scene_of(r.config);
  if (images.map_depth.empty() || images.map_size < 1) return;
  const cube::DepthRange range =
      images.map_depth_zero_to_one ? cube::DepthRange::zero_to_one : cube::DepthRange::minus_one_to_one;
  const std::string key = scene_key(r.config) + "/" + std::to_string(options_.check_frame) + "/" +
                          std::to_string(images.map_size) + "/" + std::to_string(int(range));
  auto it = map_truths_.find(key);
  if (it == map_truths_.end())
    it = map_truths_
             .emplace(key, compute_map_truth(caster_of(r.config), sc, options_.check_frame, images.map_size,
                                             range))
             .first;
  r.map_texels = check_map_texels(it->second, images, r.config.depth_format,
                                  backend(r.config.backend).device().subpixel_bits);
  add_texel_finding(r, "map_texels", *r.map_texels, kMapTexelLimitPercent);
}

// What the lighting pass read, replayed on six_pass (the reference of its group: every other technique must
// match its shadow factor bit for bit, so one replay covers the group).
void Harness::check_lookups_of(CaseResult& r, const Images& images) {
  const scene::Scene& sc = scene_of(r.config);
  if (!(r.config == reference_config(r.config))) {
    r.lookups_skipped = "held to six_pass's shadow factor, which is replayed";
    return;
  }
  r.lookups_skipped = lookup_check_skip_reason(r.config, images, sc.has_point_light);
  if (!r.lookups_skipped.empty()) return;
  LookupInputs in;
  in.filter = r.config.filter;
  in.bias = r.config.remedies.bias;
  in.light = glm::dvec3(sc.light.path.at(options_.check_frame));
  in.camera = glm::dvec3(sc.camera.position);
  in.far_plane = images.light_far;
  in.pcf_scale = r.config.pcf_scale;
  in.subtexel_bits = backend(r.config.backend).device().subtexel_bits;
  r.lookups = check_lookups(images, in);
  if (!r.lookups->ok())
    r.add({Status::failed_check,
           "lookups",
           describe(*r.lookups),
           {{"outside", double(r.lookups->outside)},
            {"pixels", double(r.lookups->pixels)},
            {"outside_percent", r.lookups->outside_percent()}}});
}

// The error against exact visibility, the --max-error limit, and the error heatmap.
void Harness::check_accuracy(CaseResult& r, const Images& images) {
  const Truth& truth = truth_for(r.config, images);
  r.accuracy = measure_accuracy(truth, images);
  const bool given = options_.max_error_percent >= 0, hard = has_hard_error_limit(r.config.filter);
  const double limit = given                        ? options_.max_error_percent
                       : hard                       ? kDefaultHardMaxErrorPercent
                       : r.config.pcf_scale == 1.0f ? kDefaultSoftMaxErrorPercent
                                                    : -1.0;
  if (limit >= 0 && r.accuracy->misclassified_percent > limit) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "shadow disagrees with exact visibility on %.3f%% of pixels (%s %g%%)",
                  r.accuracy->misclassified_percent,
                  given  ? "--max-error"
                  : hard ? "default limit for hard comparisons"
                         : "default limit for soft filters",
                  limit);
    r.add({Status::failed_quality,
           "max_error",
           buf,
           {{"misclassified_percent", r.accuracy->misclassified_percent}, {"max_error_percent", limit}}});
  }
  if (!options_.write_images()) return;
  fs::path rel = fs::path("images") / r.config.id() / "error_heatmap.png";
  fs::create_directories((fs::path(options_.out_dir) / rel).parent_path());
  write_later(r, [path = (fs::path(options_.out_dir) / rel).string(), w = images.width, h = images.height,
                  rgb = error_heatmap(truth, images)] { write_png_rgb_top_down(path, w, h, rgb); });
  r.images["error_heatmap"] = rel.string();
}

// One ray caster per loaded scene, shared by the pixel truth and the cube truth.
const reference::RayCaster& Harness::caster_of(const CaseConfig& c) {
  auto& caster = casters_[scene_key(c)];
  if (!caster) caster = std::make_unique<reference::RayCaster>(scene_of(c));
  return *caster;
}

// One truth per scene and frame, whichever API or technique asks: identical positions share it whole, and
// positions that differ by rounding (the other API's) share every pixel on the same surface point, cast again
// elsewhere.
const Truth& Harness::truth_for(const CaseConfig& c, const Images& images) {
  const std::string shared = scene_key(c) + "/" + std::to_string(options_.check_frame) + "/" +
                             std::to_string(images.width) + "x" + std::to_string(images.height);
  std::string key = shared + "/" + std::to_string(positions_fingerprint(images));
  auto it = truths_.find(key);
  if (it != truths_.end()) return it->second;
  auto prior = truth_priors_.find(shared);
  TruthPrior from;
  if (prior != truth_priors_.end()) from = {&truths_.at(prior->second.first), &prior->second.second};
  const Truth& made = truths_
                          .emplace(key, compute_truth(caster_of(c), scene_of(c), options_.check_frame, images,
                                                      options_.truth, from))
                          .first->second;
  if (prior == truth_priors_.end()) truth_priors_.emplace(shared, std::make_pair(key, images.world_position));
  return made;
}

}  // namespace omnishadow::bench
