// The truth checks: the cube's and the 2D maps' texels against exact ray casts, and each case's shadow
// against exact visibility (with the --max-error limits and the error heatmap). The ray caster and the truths
// come from the TruthCache: every case of a group shares them.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "backends/common/cube_faces.h"
#include "backends/common/layouts.h"
#include "bench/truth/case_checks.h"
#include "bench/truth/lookup_check.h"

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
  in.camera = glm::dvec3(sc.camera.position);
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

namespace {

// The world offsets a filter's taps add to the lookup vector (shaders/shadow_filters.glsl, its disk table
// read from the shader source by the lookup replay), for a point `view_distance` from the camera. PCSS's
// penumbra has no bound (its light keeps every face): only its centre tap.
std::vector<glm::vec3> tap_offsets(const CaseConfig& c, float view_distance, float range) {
  const float scale = c.pcf_scale;
  std::vector<glm::vec3> taps;
  if (c.filter == Filter::pcf_grid64) {
    const float grid = 0.1f * scale, step = grid / 2.0f;
    for (int x = 0; x < 4; ++x)
      for (int y = 0; y < 4; ++y)
        for (int z = 0; z < 4; ++z) taps.push_back(glm::vec3(-grid) + step * glm::vec3(x, y, z));
  } else if (c.filter == Filter::pcf_disk20) {
    const float radius = (1.0f + view_distance / range) / 25.0f * scale;
    for (const glm::dvec3& d : disk_directions()) taps.push_back(glm::vec3(d) * radius);
  } else {
    taps.push_back(glm::vec3(0.0f));
  }
  return taps;
}

// The faces a tap in direction d reads: the one its major axis picks, and any whose edge lies within half a
// texel (a LINEAR tap there filters across the seam).
uint8_t faces_read(const glm::vec3& d, int face_size) {
  const float slope = 1.0f + 1.0f / float(std::max(face_size, 1));
  uint8_t mask = 0;
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2;
    const float u = (f % 2 == 0 ? 1.0f : -1.0f) * d[axis];
    if (u > 0.0f && std::fabs(d[(axis + 1) % 3]) <= slope * u && std::fabs(d[(axis + 2) % 3]) <= slope * u)
      mask |= uint8_t(1u << f);
  }
  return mask;
}

}  // namespace

// View culling's own check, over every light (not only the checked ones), independent of the culling's
// geometry: every tap of every covered pixel within a light's range (the filter's kernel replayed from the
// pixel's world position) reads faces the frame drew. It skips the normal offset's shift (the normal is not
// read back); the comparison with six_pass unculled (reference_config) still holds the lit frame to the
// unculled one.
void check_view_culling(CaseFindings& r, const Images& images, const std::vector<PlannedLight>& lights,
                        const glm::vec3& camera) {
  if (!r.config.optimizations.view_culling) return;
  const std::vector<float>& p = images.world_position;
  uint64_t total = 0;
  std::string where;
  for (const PlannedLight& light : lights) {
    std::array<uint64_t, 6> missing{};
    for (size_t i = 0; i + 3 < p.size(); i += 4) {
      if (p[i + 3] != 1.0f) continue;  // nothing drawn here
      const glm::vec3 point(p[i], p[i + 1], p[i + 2]);
      const glm::vec3 d = point - light.position;
      if (glm::length(d) >= light.range) continue;  // beyond the range: the light adds nothing
      uint8_t read = 0;
      for (const glm::vec3& tap : tap_offsets(r.config, glm::length(camera - point), light.range))
        read |= faces_read(d + tap, light.face_size);
      if (light.faces == 0) read = 1u << cube::direction_to_face(d).face;  // a light out of view: any pixel
      for (int f = 0; f < 6; ++f) missing[size_t(f)] += (read & ~light.faces) >> f & 1u;
    }
    for (int f = 0; f < 6; ++f) {
      if (!missing[size_t(f)]) continue;
      total += missing[size_t(f)];
      where += std::string(where.empty() ? "" : ", ") + "light " + std::to_string(light.index) + " " +
               cube::kFaceNames[size_t(f)] + ": " + std::to_string(missing[size_t(f)]);
    }
  }
  if (total == 0) return;
  r.add({Status::failed_check,
         "view_culling",
         std::to_string(total) +
             " covered pixels within a light's range read it through faces view culling "
             "left out (" +
             where + ")",
         {{"pixels", double(total)}}});
}

}  // namespace omnishadow::bench
