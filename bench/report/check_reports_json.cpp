#include "bench/report/check_reports_json.h"

#include <cmath>

#include "backends/common/light_clusters.h"

namespace omnishadow::bench {

using nlohmann::json;

namespace {

// A cube or map texel report (bench/truth/cube_truth.h, bench/truth/map_truth.h): the fields both have.
template <typename Report>
json texels_to_json(const Report& k, const char* reference, double limit_percent) {
  json worst = json::array();
  for (const TexelFinding& w : k.worst)  // "nothing" (no surface) as null
    worst.push_back({{"layer", w.layer},
                     {"s", w.s},
                     {"t", w.t},
                     {"got", w.got < 0 ? json() : json(w.got)},
                     {"want", w.want < 0 ? json() : json(w.want)},
                     {"edge_texels", w.edge_texels < 0 ? json() : json(w.edge_texels)}});
  return {{"reference", reference},
          {"stride", k.stride},
          {"texels", k.texels},
          {"bad_percent", k.bad_percent()},
          {"wrong", k.wrong},
          {"spurious", k.spurious},
          {"missing", k.missing},
          {"max_error", k.max_error},
          {"limit_percent", limit_percent},
          {"reach_texels", k.reach_texels},
          {"worst", worst}};
}

// The update budget's sequence: each frame's faces and error, and the worst and mean.
json staleness_to_json(const StalenessReport& s) {
  const bool measured = !s.lights.empty();  // --no-accuracy measures no error
  json frames = json::array();
  for (const StalenessFrame& f : s.frames)
    frames.push_back({{"frame", f.frame},
                      {"faces_rendered", f.faces_rendered},
                      {"faces_stale", f.faces_stale},
                      {"max_wait_frames", f.max_wait},
                      {"misclassified_percent", measured ? json(f.misclassified_percent) : json(nullptr)},
                      {"pixels", f.pixels},
                      {"lights_relocated", f.lights_relocated}});
  return {{"lights", s.lights},
          {"frames", frames},
          {"wait_bound_frames", s.wait_bound},
          {"max_wait_frames", s.max_wait},
          {"mean_faces_rendered", s.mean_faces_rendered},
          {"misclassified_percent", measured ? json{{"mean", s.mean_misclassified_percent},
                                                    {"worst", s.worst_misclassified_percent},
                                                    {"worst_frame", s.worst_frame}}
                                             : json(nullptr)},
          {"truth", "exact point-light visibility of each frame, over the lights listed"}};
}

}  // namespace

json checks_to_json(const std::vector<CheckResult>& checks) {
  json out = json::array();
  for (const CheckResult& k : checks)
    out.push_back({{"name", k.name},
                   {"against", k.against},
                   {"passed", k.passed},
                   {"tolerance", k.tolerance},
                   {"max_percent_differing", k.max_percent},
                   {"max_abs_difference", k.difference.max_abs},
                   {"values_differing", k.difference.differing},
                   {"values_compared", k.difference.total},
                   {"percent_differing", k.difference.percent_differing()},
                   {"method", k.method},
                   {"values_inadmissible", k.inadmissible ? json(*k.inadmissible) : json(nullptr)},
                   {"diff_image", k.diff_image.empty() ? json(nullptr) : json(k.diff_image)}});
  return out;
}

// A many-light case's checked lights, each against its own truth; the totals beside pool them.
json per_light_to_json(const CaseResult& r) {
  json lights = {
      {"checked", "light 0 and every " + std::to_string(r.light_stride) + "th after it (light_stride)" +
                      (r.light_stride > 1 ? ", and the light farthest from the camera for its range" : "") +
                      "; accuracy above pools their pixels"},
      {"light_stride", r.light_stride},
      {"lights", json::array()}};
  if (r.lit_psnr_every_light_db)  // null: identical to the frame lit with every light's exact visibility
    lights["lit_psnr_every_light_db"] =
        *r.lit_psnr_every_light_db < 0 ? json(nullptr) : json(*r.lit_psnr_every_light_db);
  for (const LightReport& l : r.per_light) {
    json e = {{"light", l.light}};
    if (l.accuracy) e["accuracy"] = accuracy_to_json(*l.accuracy);
    if (l.cube_texels) {
      e["cube_texels"] = {{"texels", l.cube_texels->texels}, {"bad", l.cube_texels->bad()}};
      if (l.cube_texels->bad()) {  // which texels of this light's map, as a one-light case reports them
        const json full = texels_to_json(*l.cube_texels, "", kCubeTexelLimitPercent);
        for (const char* field : {"wrong", "spurious", "missing", "max_error", "worst"})
          e["cube_texels"][field] = full[field];
        e["cube_texels"]["bad_per_face"] = l.cube_texels->bad_per_face;
      }
    }
    if (l.lookups) e["lookups"] = {{"pixels", l.lookups->pixels}, {"outside", l.lookups->outside}};
    lights["lights"].push_back(e);
  }
  return lights;
}

json accuracy_to_json(const Accuracy& a) {
  auto db = [](double v) { return v < 0 ? json(nullptr) : json(v); };  // null: identical to the reference
  json j = {{"reference",
             "exact visibility by ray casting the scene's triangles (BVH) from the GPU's world positions"},
            {"pixels", a.pixels},
            {"misclassified_percent", a.misclassified_percent},
            {"false_shadow_percent", a.false_shadow_percent},
            {"missed_shadow_percent", a.missed_shadow_percent},
            {"mae_point", a.mae_point},
            {"psnr_point_db", db(a.psnr_point_db)}};
  if (a.mae_sphere >= 0) {
    j["mae_sphere"] = a.mae_sphere;
    j["psnr_sphere_db"] = db(a.psnr_sphere_db);
    j["sphere_stride"] = a.sphere_stride;  // every sphere_stride-th pixel in x and y (bench/truth/accuracy.h)
    j["sphere_pixels"] = a.sphere_pixels;
  }
  // Radii are short decimals held as floats: written rounded, not as 0.20000000298.
  auto radius = [](double r) { return std::round(r * 1e4) / 1e4; };
  std::vector<double> radii;
  for (float r : kFitRadii) radii.push_back(radius(r));
  if (a.fit_radius >= 0)
    j["radius_fit"] = {
        {"radii", radii},
        {"mae", a.fit_mae},
        {"best_radius", radius(a.fit_radius)},
        {"best_mae", a.fit_mae_best},
        {"sampling", "every " + std::to_string(fit_stride_for(a.sphere_stride)) + "th pixel in x and y, " +
                         std::to_string(kFitSamplesPerAxis * kFitSamplesPerAxis) + " rays per radius"}};
  return j;
}

// The checks' own reports: moments, texels against exact distances, lookups replayed, clustered lists.
void add_check_reports(json& j, const CaseResult& r) {
  if (r.moments)
    j["moments"] = {{"bound",
                     "the blur of the stored depths' moments, widened by each step's rounding "
                     "(bench/truth/moments_check.h)"},
                    {"values", r.moments->values},
                    {"outside", r.moments->outside},
                    {"non_finite", r.moments->non_finite}};
  if (r.cube_texels) {
    j["cube_texels"] = texels_to_json(*r.cube_texels,
                                      "exact first-hit distance along each checked texel centre's "
                                      "direction",
                                      kCubeTexelLimitPercent);
    j["cube_texels"]["bad_per_face"] = r.cube_texels->bad_per_face;
  }
  if (r.lookups)
    j["lookups"] = {{"bound",
                     "every texel within the sampler's sub-texel precision and the direction's rounding "
                     "of the cube-map rule's, comparisons within 1e-4 (bench/truth/lookup_check.h)"},
                    {"pixels", r.lookups->pixels},
                    {"outside", r.lookups->outside},
                    {"taps", r.lookups->taps},
                    {"ambiguous_taps", r.lookups->ambiguous_taps}};
  else if (!r.lookups_skipped.empty())
    j["lookups"] = {{"skipped", r.lookups_skipped}};
  if (r.map_texels) {
    j["map_texels"] = texels_to_json(*r.map_texels,
                                     "exact window depth of the first kept surface along each "
                                     "checked texel's ray",
                                     kMapTexelLimitPercent);
    j["map_texels"]["bad_per_map"] = r.map_texels->bad_per_map;
  }
  if (r.light_clusters)
    j["light_clusters"] = {{"clusters", r.light_clusters->clusters},
                           {"tile_pixels", gpu::kClusterTilePixels},
                           {"slices", gpu::kClusterSlices},
                           {"mean_lights_listed", r.light_clusters->mean_listed},
                           {"mean_lights_reaching", r.light_clusters->mean_reaching},
                           {"max_lights_listed", r.light_clusters->max_listed}};
  if (r.staleness) j["staleness"] = staleness_to_json(*r.staleness);
}

}  // namespace omnishadow::bench
