// The image checks: the timed variant against the check variant, every technique against the
// six_pass rendering of its group (cube faces, shadow factor, lit frame, with the driver's evidence when the
// images point at it), and each case against the same case on the other API. A failing check writes its diff
// image.

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "backends/common/cube_faces.h"
#include "backends/common/layouts.h"
#include "backends/common/techniques.h"
#include "bench/truth/case_checks.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;

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
  // Faces view culling left out hold a clear or an earlier frame: evidence of nothing.
  if (img.view_faces != cube::kAllFaces || ref.view_faces != cube::kAllFaces) return "";
  if (all_faces_identical(img) && !all_faces_identical(ref))
    return "all six faces hold the same image while six_pass's differ: the driver rendered every layer/view "
           "into one face";
  std::vector<int> mine = untouched_faces(img, far_plane), theirs = untouched_faces(ref, far_plane);
  std::vector<int> lost;
  for (int f : mine)
    if (std::find(theirs.begin(), theirs.end(), f) == theirs.end()) lost.push_back(f);
  if (lost.empty()) return "";
  std::string names;
  for (int f : lost)
    names += (names.empty() ? "" : " ") + std::string(cube::kFaceNames[static_cast<size_t>(f)]);
  return std::to_string(lost.size()) + " of 6 faces (" + names +
         ") were never written while six_pass wrote them: the driver did not route every layer/view to its "
         "face";
}

std::map<std::string, double> check_figures(const CheckResult& c) {
  std::map<std::string, double> figures = {{"percent_differing", c.difference.percent_differing()},
                                           {"max_abs", c.difference.max_abs},
                                           {"differing", double(c.difference.differing)}};
  if (c.inadmissible) figures["inadmissible"] = double(*c.inadmissible);
  return figures;
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// What a technique's check allows beyond six_pass's exact values: the stored distances' tolerance (world
// units), and whether the shadow factor and the lit image may differ in --cross-max-percent of their values.
struct TechniqueAllowance {
  double face_tolerance;
  bool images_may_differ;
};

TechniqueAllowance technique_allowance(const CaseConfig& c, double face_tolerance, double near_plane,
                                       double far_plane) {
  TechniqueAllowance a{face_tolerance, false};
  // Outside the cube, a layout's stored distance comes from the world position interpolated across triangles
  // projected by a warp (dual_paraboloid, w = 1) or an asymmetric frustum (tetrahedral); pipelines with and
  // without a geometry stage may set that interpolation up from window coordinates that round differently
  // (llvmpipe's differed by 2-19 ulps of the distance, on whole triangles; its cube faces, whose matrices
  // hold 0 and +-1 beside the translation, agree bit for bit, and the cube is held to that). GL asks of each
  // float operation a relative error of 1e-5 (GL 4.5, 2.3.4.1); the interpolation and the length are about
  // ten of them, so stored distances may differ by 1e-4 of the far plane, the bound the cube texel check
  // allows for the same interpolation. A lookup whose receiver sits within that of a stored distance may then
  // compare the other way: the shadow factor and the lit image may differ in as few values as across backends
  // (cross_max_percent), whose pipelines differ in the same last bits. Vertex positions that round
  // differently also move triangle edges by as much: a texel whose centre lies on an edge may be covered by
  // the triangle on either side (GL 4.5 appendix A asks the same results of one program and state, not of
  // two). So the faces may differ beyond the tolerance in as few texels as the images, and only where both
  // values are ones a conformant rasteriser may store there (the cube texel check's rule, texel_admissible).
  if (traits(c.layout).geometry.map != TexelMap::cube_faces) {  // warped or asymmetric
    a.face_tolerance = std::max(a.face_tolerance, 1e-4 * far_plane);
    a.images_may_differ = true;
  }
  // nv_swizzle with a storage that writes no depth (r32f_distance) keeps the nearest fragment by a reversed
  // depth, near / w, where six_pass keeps it by its projective depth A + B / w (|B| = near far / (far - near)
  // for D32F's [0, 1]); both are affine in the interpolated 1 / w, so they order fragments alike except where
  // six_pass's depth rounds two of them together. Its float depth near 1 has a unit roundoff of 2^-24;
  // allowing 8 of them (the interpolation's few operations, either side) fragments whose w differ by dw = 8
  // 2^-24 w^2 / |B| can swap, and their stored distances then differ by up to sqrt 3 dw (a distance is at
  // most sqrt 3 times its axis), largest at w = far. The colours written are the fragments' own, so only such
  // ties differ; lookups near them may then compare the other way, as across backends (cross_max_percent).
  // nv_swizzle's clip position is the light-relative position permuted by each face's swizzle, not the face
  // matrix's product: the rasteriser sets up the same triangle's interpolation from other clip coordinates,
  // which round differently (the hall's pillars and crates: 4.5% of texels 2e-6 of far apart on llvmpipe,
  // where the room's axis-aligned walls agree bit for bit). The same bound as a warped layout's then holds.
  if (c.technique == Technique::nv_swizzle) {
    a.face_tolerance = std::max(a.face_tolerance, 1e-4 * far_plane);
    a.images_may_differ = true;
  }
  // The viewport transform x_w = o + s x_ndc (s = N / 2 for a layer of N texels, o its centre: the atlas's
  // tile offset added) is exact when s is a power of two and o an integer plus s: the product is exact, so an
  // implementation that fuses it with the add rounds as one that does not. Otherwise it rounds once or twice
  // depending on how a pipeline arranges it, and a single pass (a geometry stage, or a viewport the shader
  // picks) need not arrange it as six_pass's vertex-only pipeline does: llvmpipe and lavapipe's geometry
  // shaders store cube 48 and 96 up to 2e-5 units apart on the hall (5-6% of texels), and an atlas's vs_layer
  // at 48 too, while every power of two agrees bit for bit. The interpolation that follows is the warped
  // layouts', so their bound holds.
  if (traits(c.technique).passes == 1 && !std::has_single_bit(unsigned(layer_size(c.layout, c.cube_size)))) {
    a.face_tolerance = std::max(a.face_tolerance, 1e-4 * far_plane);
    a.images_may_differ = true;
  }
  if (reversed_depth_test(c)) {
    const double n = near_plane, f = far_plane;
    a.face_tolerance =
        std::max(a.face_tolerance, std::sqrt(3.0) * 8.0 * std::ldexp(1.0, -24) * f * (f - n) / n);
    a.images_may_differ = true;
  }
  return a;
}

}  // namespace

// The case every other case of its group is checked against: six_pass without culling or caching (which must
// not change a single value). fit_range stays: it changes the stored depth's scale, so it has its own
// reference.
CaseConfig reference_config(const CaseConfig& c) {
  CaseConfig k = c;
  k.technique = Technique::six_pass;
  k.light_grouping = LightGrouping::per_light;
  k.optimizations.face_culling = false;
  k.optimizations.static_cache = false;
  // Unculled: a case culled to the view must light the frame as if every light and face had been drawn.
  k.optimizations.view_culling = false;
  k.optimizations.light_clusters = false;  // and every light looped over at every pixel
  k.update_budget_faces = 0;  // and every stale face refreshed (the check frame's maps are whole anyway)
  return k;
}

std::string group_key(const CaseConfig& c) { return reference_config(c).id(); }

int face_edge(const Images& img) {
  return img.has_full_cube() ? img.cube_size : img.cube_size / std::max(img.cube_sample_stride, 1);
}

std::vector<float> concat_faces(const Images& img, uint8_t faces_kept) {
  // Faces side by side, face order left to right, so one PNG shows the whole cube (the check grid when only
  // that came back: every stride-th texel).
  const int n = face_edge(img);
  const auto& faces = img.has_full_cube() ? img.cube_distance : img.cube_sample;
  std::vector<float> strip(static_cast<size_t>(n) * static_cast<size_t>(n) * 6);
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < n && faces[size_t(f)].size() >= size_t(n) * size_t(n) && (faces_kept >> f & 1u); ++y)
      std::copy_n(faces[static_cast<size_t>(f)].begin() + static_cast<ptrdiff_t>(y) * n, n,
                  strip.begin() + (static_cast<ptrdiff_t>(y) * 6 + f) * n);
  return strip;
}

CheckResult timed_variant_check(const std::vector<uint8_t>& timed,
                                const std::vector<uint8_t>& check_variant) {
  CheckResult check{"timed_lit", "check variant"};
  check.difference = compare_values(timed, check_variant, 0.0);
  check.max_percent = kTimedLitMaxPercent;
  check.max_abs = 1.0;
  check.passed =
      check.difference.percent_differing() <= check.max_percent && check.difference.max_abs <= check.max_abs;
  return check;
}

// Judges a check from its difference and its limits, and has a failed one's diff image written.
static void record_check(CaseFindings& r, CheckResult c, const std::vector<float>& a,
                         const std::vector<float>& b, const std::vector<float>& grey, int width, int height,
                         double scale, bool flip, const CheckContext& ctx) {
  c.passed =
      (c.max_percent > 0 ? c.difference.percent_differing() <= c.max_percent : c.difference.differing == 0) &&
      (c.max_abs < 0 || c.difference.max_abs <= c.max_abs) && c.inadmissible.value_or(0) == 0;
  if (!c.passed && ctx.write_image) {
    c.diff_image = (fs::path("images") / r.config.id() / ("diff_" + c.name + ".png")).string();
    ctx.write_image(c.diff_image, width, height,
                    diff_image_rgb(a, b, grey, width, height, c.tolerance, scale, flip));
  }
  r.checks.push_back(c);
}

void check_timed_variant(CaseFindings& r, const Images& images, const CheckContext& ctx) {
  CheckResult check = timed_variant_check(images.timed_lit_rgba8, images.lit_rgba8);
  check.against = r.config.id() + " (check variant)";
  std::vector<float> diff = max_channel_difference(images.timed_lit_rgba8, images.lit_rgba8);
  record_check(r, check, diff, std::vector<float>(diff.size(), 0.0f), luminance(images.lit_rgba8),
               images.width, images.height, 64.0, true, ctx);
  if (!r.checks.back().passed)
    r.add({Status::failed_check, "timed_lit",
           "timed_lit: the timed lighting variant's colour differs from the check variant's in " +
               fmt(check.difference.percent_differing()) + "% of values (max abs " +
               fmt(check.difference.max_abs) + "; allowed: 1 level in " + fmt(kTimedLitMaxPercent) +
               "%): the timed frame does not render what was checked",
           check_figures(check)});
}

bool cubes_equal_by_hash(const Images& images, const Images& reference) {
  return images.cube_summary_on_device == reference.cube_summary_on_device &&
         images.cube_summary == reference.cube_summary && reference.light_far == images.light_far;
}

// Of two strips of faces side by side (concat_faces: each `edge` texels square, faces left to right), the
// texels that differ beyond `tolerance` where either value is one `admissible` refuses at that texel.
static uint64_t inadmissible_differences(const std::vector<float>& a, const std::vector<float>& b, int edge,
                                         double tolerance, const TexelAdmissible& admissible) {
  const size_t width = 6 * size_t(edge);
  uint64_t refused = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    if (a[i] == b[i] || std::fabs(double(a[i]) - double(b[i])) <= tolerance) continue;
    const int x = int(i % width), t = int(i / width), layer = x / edge, s = x % edge;
    if (!admissible(layer, s, t, a[i]) || !admissible(layer, s, t, b[i])) ++refused;
  }
  return refused;
}

void check_against_reference(CaseFindings& r, const Images& images, const Images& ref,
                             const CheckContext& ctx, const TexelAdmissible& admissible) {
  const CheckOptions& options = ctx.options;
  const std::string ref_id = reference_config(r.config).id();
  const float far_plane = ref.light_far;

  // Cube faces, in world units: the technique must store what six_pass stores. Equal face hashes (the
  // device's, or the host's for full read-backs) settle it without the values; otherwise both cubes are
  // compared value by value (the caller read them in full: frames are deterministic).
  CheckResult faces_check{"cube_faces", ref_id};
  const TechniqueAllowance allowance =
      technique_allowance(r.config, options.face_tolerance, ctx.scene.light().near_plane, far_plane);
  faces_check.tolerance = allowance.face_tolerance;
  if (cubes_equal_by_hash(images, ref)) {
    const uint64_t texels = 6ull * uint64_t(images.cube_size) * uint64_t(images.cube_size);
    faces_check.difference = {texels, 0, 0.0};
    faces_check.method = "hash";
    faces_check.passed = true;
    r.checks.push_back(faces_check);
  } else {
    // View culling: only the faces both frames drew hold what their lookups read.
    const uint8_t drawn = images.view_faces & ref.view_faces;
    std::vector<float> faces = concat_faces(images, drawn), ref_faces = concat_faces(ref, drawn);
    faces_check.difference = compare_values(faces, ref_faces, faces_check.tolerance);
    // Coverage may flip at edges: a few such texels, each judged at its own texel (so both cubes in full).
    // Beyond the few the check fails unjudged: a broken pass differs in many texels, each a ray cast or more.
    if (allowance.images_may_differ && admissible && images.has_full_cube() && ref.has_full_cube()) {
      faces_check.max_percent = options.cross_max_percent;
      // With nothing beyond the tolerance there is nothing to judge: no scan of every texel (25 M at 2048).
      if (faces_check.difference.differing == 0)
        faces_check.inadmissible = 0;
      else if (faces_check.difference.percent_differing() <= faces_check.max_percent)
        faces_check.inadmissible =
            inadmissible_differences(faces, ref_faces, face_edge(images), faces_check.tolerance, admissible);
    }
    record_check(r, faces_check, faces, ref_faces, scaled(ref_faces, 1.0f / far_plane), images.cube_size * 6,
                 images.cube_size, far_plane * 0.05, false, ctx);
  }

  // Where the stored values may differ, the images may as across backends: a moments filter's shadow factor
  // moves by a few ulps with them, a lookup at a tie flips.
  CheckResult shadow_check{"shadow_factor", ref_id};
  shadow_check.tolerance = allowance.images_may_differ ? options.cross_shadow_tolerance : 0.0;
  if (allowance.images_may_differ) shadow_check.max_percent = options.cross_max_percent;
  shadow_check.difference = compare_values(images.shadow_factor, ref.shadow_factor, shadow_check.tolerance);
  record_check(r, shadow_check, images.shadow_factor, ref.shadow_factor, ref.shadow_factor, images.width,
               images.height, 1.0, true, ctx);

  CheckResult lit_check{"lit", ref_id};
  lit_check.tolerance = options.lit_tolerance;
  if (allowance.images_may_differ) lit_check.max_percent = options.cross_max_percent;
  lit_check.difference = compare_values(images.lit_rgba8, ref.lit_rgba8, options.lit_tolerance);
  std::vector<float> lit_diff = max_channel_difference(images.lit_rgba8, ref.lit_rgba8);
  record_check(r, lit_check, lit_diff, std::vector<float>(lit_diff.size(), 0.0f), luminance(ref.lit_rgba8),
               images.width, images.height, 64.0, true, ctx);

  bool failed = false;
  for (const CheckResult& c : r.checks)
    if (!c.passed && (c.name == "cube_faces" || c.name == "shadow_factor" || c.name == "lit")) {
      failed = true;
      r.add({Status::failed_check, c.name,
             c.name + " differ from " + c.against + " in " + fmt(c.difference.percent_differing()) +
                 "% of values (max abs " + fmt(c.difference.max_abs) +
                 (c.inadmissible ? "; " + std::to_string(*c.inadmissible) +
                                       " of them hold a value no rasteriser may store there; allowed: values "
                                       "a coverage flip at a triangle edge may store, in " +
                                       fmt(c.max_percent) + "%"
                                 : std::string()) +
                 ")",
             check_figures(c)});
    }
  if (failed)
    if (std::string evidence = driver_evidence(images, ref, far_plane); !evidence.empty())
      r.add({Status::failed_check, "driver_evidence", evidence, {}});
}

void check_against_other_api(CaseFindings& r, const Images& images, const CrossReference& ref,
                             const CheckContext& ctx) {
  const CheckOptions& options = ctx.options;
  CheckResult shadow{"cross_backend_shadow_factor", ref.case_id};
  shadow.tolerance = options.cross_shadow_tolerance;
  shadow.max_percent = options.cross_max_percent;
  shadow.difference = compare_values(images.shadow_factor, ref.shadow_factor, options.cross_shadow_tolerance);
  record_check(r, shadow, images.shadow_factor, ref.shadow_factor, ref.shadow_factor, images.width,
               images.height, 1.0, true, ctx);
  CheckResult lit{"cross_backend_lit", ref.case_id};
  lit.tolerance = options.cross_lit_tolerance;
  lit.max_percent = options.cross_max_percent;
  lit.difference = compare_values(images.lit_rgba8, ref.lit, options.cross_lit_tolerance);
  std::vector<float> lit_diff = max_channel_difference(images.lit_rgba8, ref.lit);
  record_check(r, lit, lit_diff, std::vector<float>(lit_diff.size(), 0.0f), luminance(ref.lit), images.width,
               images.height, 64.0, true, ctx);
  for (const CheckResult* c : {&r.checks[r.checks.size() - 2], &r.checks.back()})
    if (!c->passed)
      r.add({Status::failed_check, c->name,
             c->name + ": " + fmt(c->difference.percent_differing()) + "% of values differ from " +
                 c->against + " (allowed " + fmt(c->max_percent) + "%)",
             check_figures(*c)});
}

}  // namespace omnishadow::bench
