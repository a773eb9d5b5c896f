// The truth checks: the cube's and the 2D maps' texels against exact ray casts, and each case's shadow
// against exact visibility (with the --max-error limits and the error heatmap). The ray caster and the truths
// come from the TruthCache: every case of a group shares them.

#include <cstdio>
#include <filesystem>

#include "backends/common/layouts.h"
#include "bench/truth/case_checks.h"

namespace omnishadow::bench {

namespace fs = std::filesystem;

namespace {

// A cube or map whose checked texels are wrong beyond `limit_percent` fails its case. One texel alone can be
// a tie at an edge through its centre (a 2-texel cube has 24 texels in all), so it takes more than one.
template <typename Report>
void add_texel_finding(CaseFindings& r, const char* check, const Report& report, double limit_percent) {
  if (report.bad_percent() <= limit_percent || report.bad() <= 1) return;
  r.add({Status::failed_check,
         check,
         describe(report),
         {{"bad_percent", report.bad_percent()},
          {"max_error", report.max_error},
          {"texels", double(report.texels)}}});
}

}  // namespace

void check_cube(CaseFindings& r, const Images& images, const CheckContext& ctx, TruthCache& truths) {
  const scene::Scene& sc = ctx.scene;
  if (!sc.has_point_light() || images.cube_size < 1) return;
  const glm::vec3 light = sc.light().path.at(ctx.options.check_frame);
  const CubeTruth& truth =
      truths.cube_truth(r.config, sc, light, sc.light().near_plane, images.light_far, images.cube_size);
  r.cube_texels = check_cube_texels(truth, images, r.config.storage, r.config.depth_format,
                                    sc.light().near_plane, ctx.device.subpixel_bits);
  // A paraboloid's rasterised triangles have straight edges where the exact map draws curves: its texels
  // differ from the exact ones by the layout's own error, which depends on tessellation. That is a figure
  // (results.json cube_texels), not a failed check; its technique checks (equal to six_pass) and exact
  // visibility still judge.
  if (!traits(r.config.layout).geometry.texels_exact) return;
  add_texel_finding(r, "cube_texels", *r.cube_texels, kCubeTexelLimitPercent);
}

// Not a texel limit: the bound is rounding only, so one moment outside it is a device storing other moments.
void check_moment_cube(CaseFindings& r, const Images& images) {
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

void check_maps(CaseFindings& r, const Images& images, const CheckContext& ctx, TruthCache& truths) {
  if (images.map_depth.empty() || images.map_size < 1) return;
  const cube::DepthRange range =
      images.map_depth_zero_to_one ? cube::DepthRange::zero_to_one : cube::DepthRange::minus_one_to_one;
  const MapTruth& truth =
      truths.map_truth(r.config, ctx.scene, ctx.options.check_frame, images.map_size, range);
  r.map_texels = check_map_texels(truth, images, r.config.depth_format, ctx.device.subpixel_bits);
  add_texel_finding(r, "map_texels", *r.map_texels, kMapTexelLimitPercent);
}

// What the lighting pass read, replayed on six_pass (the reference of its group: every other technique must
// match its shadow factor bit for bit, so one replay covers the group).
void check_lookups_of(CaseFindings& r, const Images& images, const CheckContext& ctx) {
  const scene::Scene& sc = ctx.scene;
  if (!(r.config == reference_config(r.config))) {
    r.lookups_skipped = "held to six_pass's shadow factor, which is replayed";
    return;
  }
  r.lookups_skipped = lookup_check_skip_reason(r.config, images, sc.has_point_light());
  if (!r.lookups_skipped.empty()) return;
  LookupInputs in;
  in.filter = r.config.filter;
  in.bias = r.config.remedies.bias;
  in.light = glm::dvec3(sc.light().path.at(ctx.options.check_frame));
  in.camera = glm::dvec3(sc.camera.at(ctx.options.check_frame).position);
  in.far_plane = images.light_far;
  in.pcf_scale = r.config.pcf_scale;
  in.subtexel_bits = ctx.device.subtexel_bits;
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
void check_accuracy(CaseFindings& r, const Images& images, const CheckContext& ctx, TruthCache& truths) {
  const CheckOptions& options = ctx.options;
  const Truth& truth = truths.truth(r.config, ctx.scene, options.check_frame, images, options.truth);
  r.accuracy = measure_accuracy(truth, images);
  const bool given = options.max_error_percent >= 0, hard = has_hard_error_limit(r.config.filter);
  const double limit = given                        ? options.max_error_percent
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
  if (!ctx.write_image) return;
  const std::string rel = (fs::path("images") / r.config.id() / "error_heatmap.png").string();
  ctx.write_image(rel, images.width, images.height, error_heatmap(truth, images));
  r.images["error_heatmap"] = rel;
}

}  // namespace omnishadow::bench
