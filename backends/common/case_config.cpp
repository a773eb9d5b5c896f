#include "backends/common/case_config.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <utility>

#include "backends/common/layouts.h"
#include "backends/common/paraboloid.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"
#include "backends/common/tetrahedron.h"

namespace omnishadow {
namespace {

template <typename E, size_t N>
using Names = std::array<std::pair<E, std::string_view>, N>;

// Spellings come from each axis's table: its rows' `name` (techniques.h, layouts.h, storage_filter_tables.h).
template <typename E, typename Row, size_t N>
constexpr Names<E, N> names_from(const std::array<Row, N>& rows, E Row::*value) {
  Names<E, N> names{};
  for (size_t i = 0; i < N; ++i) names[i] = {rows[i].*value, rows[i].name};
  return names;
}
constexpr auto kTechniqueNames = names_from(kTechniques, &TechniqueTraits::technique);
constexpr auto kLayoutNames = names_from(kLayouts, &LayoutTraits::layout);
constexpr auto kFilters = names_from(kFilterTable, &FilterTraits::filter);
constexpr auto kStorages = names_from(kStorageTable, &StorageTraits::storage);
constexpr Names<DepthFormat, 3> kDepthFormats = {
    {{DepthFormat::d16, "d16"}, {DepthFormat::d24, "d24"}, {DepthFormat::d32f, "d32f"}}};
constexpr Names<LightGrouping, 2> kLightGroupings = {
    {{LightGrouping::per_light, "per_light"}, {LightGrouping::all_lights, "all_lights"}}};
constexpr Names<AtlasTiles, 3> kAtlasTiles = {{{AtlasTiles::uniform, "uniform"},
                                               {AtlasTiles::by_distance, "by_distance"},
                                               {AtlasTiles::by_coverage, "by_coverage"}}};

template <typename E>
struct Table;
template <>
struct Table<Technique> {
  static constexpr auto& names = kTechniqueNames;
  static constexpr const char* what = "technique";
};
template <>
struct Table<Filter> {
  static constexpr auto& names = kFilters;
  static constexpr const char* what = "filter";
};
template <>
struct Table<Storage> {
  static constexpr auto& names = kStorages;
  static constexpr const char* what = "storage";
};
template <>
struct Table<DepthFormat> {
  static constexpr auto& names = kDepthFormats;
  static constexpr const char* what = "depth format";
};
template <>
struct Table<Layout> {
  static constexpr auto& names = kLayoutNames;
  static constexpr const char* what = "layout";
};
template <>
struct Table<LightGrouping> {
  static constexpr auto& names = kLightGroupings;
  static constexpr const char* what = "light grouping";
};
template <>
struct Table<AtlasTiles> {
  static constexpr auto& names = kAtlasTiles;
  static constexpr const char* what = "atlas tiling";
};

template <typename E>
std::string_view name_of(E v) {
  for (const auto& [value, name] : Table<E>::names)
    if (value == v) return name;
  return "?";
}

}  // namespace

std::string_view to_string(Technique v) { return name_of(v); }
std::string_view to_string(Filter v) { return name_of(v); }
std::string_view to_string(Storage v) { return name_of(v); }
std::string_view to_string(DepthFormat v) { return name_of(v); }
std::string_view to_string(Layout v) { return name_of(v); }
std::string_view to_string(LightGrouping v) { return name_of(v); }
std::string_view to_string(AtlasTiles v) { return name_of(v); }

template <typename E>
std::string valid_values() {
  std::string out;
  for (const auto& [value, name] : Table<E>::names) out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

template <typename E>
E parse_enum(std::string_view text) {
  for (const auto& [value, name] : Table<E>::names)
    if (name == text) return value;
  throw std::invalid_argument("unknown " + std::string(Table<E>::what) + " '" + std::string(text) +
                              "' (valid: " + valid_values<E>() + ")");
}

template <typename E>
std::vector<E> all_values() {
  std::vector<E> out;
  for (const auto& [value, name] : Table<E>::names) out.push_back(value);
  return out;
}

#define OMNISHADOW_INSTANTIATE(E)             \
  template E parse_enum<E>(std::string_view); \
  template std::vector<E> all_values<E>();    \
  template std::string valid_values<E>();
OMNISHADOW_INSTANTIATE(Technique)
OMNISHADOW_INSTANTIATE(Filter)
OMNISHADOW_INSTANTIATE(Storage)
OMNISHADOW_INSTANTIATE(DepthFormat)
OMNISHADOW_INSTANTIATE(Layout)
OMNISHADOW_INSTANTIATE(LightGrouping)
OMNISHADOW_INSTANTIATE(AtlasTiles)
#undef OMNISHADOW_INSTANTIATE

namespace {
// Each moments knob only means something to the filters that read it (parse_moments_tuning's list).
Support moments_tuning_support(Filter filter, const MomentsTuning& t) {
  const MomentsTuning d;
  const std::optional<Storage> own = traits(filter).own_storage;
  const MomentKind kind = own ? traits(*own).moments : MomentKind::none;
  const std::string name(to_string(filter));
  if (t.bleed_reduction != d.bleed_reduction && kind != MomentKind::vsm && kind != MomentKind::evsm &&
      kind != MomentKind::msm)
    return {
        false,
        "bleed reduction (lbr) applies to the Chebyshev and Hamburger bounds (vsm, evsm2, evsm4, msm), not " +
            name};
  if (t.exponent_fraction != d.exponent_fraction && kind != MomentKind::esm && kind != MomentKind::evsm)
    return {false, "an exponent (exp) belongs to the warped moments (esm, evsm2, evsm4), not " + name};
  if (t.floor_scale != d.floor_scale && kind != MomentKind::vsm && kind != MomentKind::msm)
    return {false, "a variance floor or moment bias (floor) belongs to vsm and msm, not " + name};
  if (t.world_units && kind != MomentKind::vsm)
    return {false,
            "world-unit distances (world) are a vsm storage variant (the warps and msm's bias assume z in "
            "[0, 1]), not " +
                name};
  return {};
}
// Layout atlas routes faces by viewport; --atlas-tiles belongs to it alone.
Support atlas_support(const CaseConfig& c) {
  if (c.layout == Layout::atlas) {
    const std::string technique(to_string(c.technique));
    if (c.technique == Technique::multiview || c.technique == Technique::mesh_shader)
      return {
          false,
          "atlas routes each face to its tile by viewport (one layer): six_pass, geometry_shader, "
          "geometry_shader_instanced, vs_layer and nv_swizzle do; " +
              technique +
              (c.technique == Technique::multiview ? " routes by view (multiview has one viewport for all)"
                                                   : " routes each primitive by layer here")};
    if (c.light_grouping == LightGrouping::all_lights)
      return {false, "every light in one pass into an atlas needs 6 viewports a light (16 on most devices)"};
    if (c.shadow_budget_texels && c.atlas_tiles != AtlasTiles::by_coverage)
      return {false, "--shadow-budget sizes the tiles by coverage (--atlas-tiles by_coverage), not " +
                         std::string(to_string(c.atlas_tiles))};
  } else if (c.atlas_tiles != AtlasTiles::uniform) {
    return {false, "--atlas-tiles " + std::string(to_string(c.atlas_tiles)) +
                       " sizes an atlas's tiles; layout " + std::string(to_string(c.layout)) +
                       " gives every light --cube"};
  }
  return {};
}

// Every light in one pass: vs_layer's instances, the geometry shader's invocations or mesh_shader's task
// workgroups (one per meshlet group and light).
Support all_lights_support(const CaseConfig& c) {
  if (c.light_grouping == LightGrouping::all_lights) {
    const bool routes_faces =
        c.technique == Technique::geometry_shader || c.technique == Technique::mesh_shader;
    if (c.technique != Technique::vs_layer && !routes_faces)
      return {
          false,
          "every light in one pass is built for vs_layer (an instance per light and face), "
          "geometry_shader (32 invocations, each routing a triangle to two lights' faces) and mesh_shader "
          "(a task workgroup per meshlet group and light); " +
              std::string(to_string(c.technique)) + " renders per light"};
    if (routes_faces && traits(c.layout).geometry.map != TexelMap::cube_faces)
      return {false, "every light in one " + std::string(to_string(c.technique)) +
                         " pass routes each light's six cube faces; " + std::string(to_string(c.layout)) +
                         " has layers of its own"};
    if (c.technique == Technique::geometry_shader && c.light_count > kAllLightsGeometryMaxLights)
      return {false, "every light in one geometry shader pass reaches " +
                         std::to_string(kAllLightsGeometryMaxLights) +
                         " lights (32 invocations, the least every device allows, of two lights each), not " +
                         std::to_string(c.light_count)};
    if (c.optimizations.face_culling)
      return {
          false,
          routes_faces
              ? "face culling with every light in one pass: " + std::string(to_string(c.technique)) +
                    " culls per light and face already"
              : "face culling with every light in one pass: the per-object masks cover one light's faces"};
    if (c.moments.world_units)
      return {false,
              "moments in world units with every light in one pass: one clear value for every light's far"};
    if (c.optimizations.view_culling)
      return {false,
              "view culling with every light in one pass: the pass draws every light's faces (cull per light "
              "with --light-grouping per_light)"};
  }
  return {};
}

Support update_budget_support(const CaseConfig& c) {
  if (c.update_budget_faces == 0) return {};
  if (c.update_budget_faces < 0) return {false, "the update budget must be at least 1 face a frame"};
  if (c.light_grouping == LightGrouping::all_lights)
    return {false, "an update budget with every light in one pass: the pass renders every light's faces"};
  if (c.optimizations.static_cache)
    return {false,
            "an update budget keeps the faces whose light stands still itself (static caching's "
            "saving, face by face): cache adds nothing"};
  if (!refreshes_single_faces(c) && c.update_budget_faces < cube::kFaceCount)
    return {false, "an update budget of " + std::to_string(c.update_budget_faces) +
                       " face(s): " + std::string(to_string(c.technique)) +
                       " refreshes a light's six faces together here (one pass, an atlas block or the "
                       "moments blur), so the budget must be at least 6"};
  return {};
}

}  // namespace

bool refreshes_single_faces(const CaseConfig& c) {
  return traits(c.technique).passes == cube::kFaceCount && c.layout != Layout::atlas &&
         traits(c.layout).geometry.layers == cube::kFaceCount &&
         traits(c.filter).prefilter != Prefilter::separable_blur;
}

bool light_cubes(const CaseConfig& c) { return c.layout == Layout::cube && c.light_count > 1; }

Support common_support(const CaseConfig& c) {
  if (traits(c.layout).geometry.map != TexelMap::cube_faces) {
    const std::string name(to_string(c.layout));
    if (c.technique != Technique::six_pass && c.technique != Technique::geometry_shader)
      return {false, name + " is drawn by six_pass (one pass per layer) and geometry_shader so far"};
    if (c.storage != Storage::linear_depth && c.storage != Storage::r32f_distance)
      return {false,
              name +
                  " stores a distance (linear_depth or r32f_distance): its read-back converts no projective "
                  "depth, and its moments filters are not built yet"};
    if (c.optimizations.face_culling)
      return {false, "face culling: the plans cull against cube faces' frusta, not hemispheres"};
    if (c.lookup_perturb_texels != 0.0f) return {false, "--lookup-perturb moves cube lookups only"};
  }
  if (Support s = atlas_support(c); !s.ok) return s;
  if (c.filter == Filter::hw_compare2x2 && c.storage != Storage::linear_depth)
    return {false, "hw_compare2x2 compares against linear distance / far (storage linear_depth); " +
                       std::string(to_string(c.storage)) +
                       (traits(c.storage).checked == DistanceEncoding::colour_distance
                            ? " stores distance in a colour texture"
                        : traits(c.storage).checked == DistanceEncoding::projective_depth
                            ? " stores projective depth"
                            : " is a moments filter's storage (its own filter reads it)")};
  if (!filter_reads(c.filter, c.storage))
    return {false, std::string(to_string(c.filter)) + " reads " +
                       (traits(c.filter).own_storage ? std::string(to_string(*traits(c.filter).own_storage))
                                                     : std::string("a stored distance")) +
                       ", not " + std::string(to_string(c.storage))};
  if (Support s = moments_tuning_support(c.filter, c.moments); !s.ok) return s;
  if (traits(c.filter).prefilter == Prefilter::separable_blur && c.cube_size < 4)
    return {false,
            "the moments blur needs a cube of at least 4 texels a side (a tap folds across one seam only)"};
  if (c.cube_size < 1 || c.width < 1 || c.height < 1)
    return {false, "cube and frame sizes must be at least 1"};
  if (c.light_count < 1) return {false, "the light count must be at least 1"};
  if (Support s = all_lights_support(c); !s.ok) return s;

  if (c.light_count > kLightCubes && c.layout == Layout::cube)
    return {false, std::to_string(c.light_count) +
                       " point lights in layout cube (one cube, one sampler per light): " +
                       std::to_string(kLightCubes) +
                       " at most (a fragment stage samples 16 textures at the least every device allows); "
                       "--layout cube_array holds every light's cube in one texture"};
  if (light_cubes(c) && c.optimizations.light_clusters)
    return {
        false,
        "clustered light lists pick a pixel's lights per pixel, and an array of samplers takes only an index "
        "every invocation shares (dynamically uniform): layout cube with several lights loops over every "
        "light; --layout cube_array takes any index"};
  if (c.technique == Technique::nv_swizzle && c.storage == Storage::hardware_depth)
    return {false,
            "nv_swizzle's clip z is the near plane (a swizzle cannot scale it per face), so the rasteriser's "
            "depth is not the face projection's that hardware_depth stores"};
  if (c.technique == Technique::nv_swizzle && c.raster_perturb_steps != 0.0f)
    return {false, "--raster-perturb moves clip positions before the swizzle could permute them"};
  if (Support s = update_budget_support(c); !s.ok) return s;
  if (c.optimizations.face_culling && traits(c.technique).culling == CullingForm::unsupported)
    return {false,
            "face culling: a multiview pass renders every view of each draw (the view mask is per render "
            "pass), so there is nothing to cull per face"};
  return {};
}

Support layer_count_support(const CaseConfig& c, int max_layers, const std::string& limit) {
  if (c.layout == Layout::atlas) return {};  // one layer: its size is the limit (atlas::too_large)
  const long long layers = static_cast<long long>(traits(c.layout).geometry.layers) * c.light_count;
  if (layers <= max_layers) return {};
  return {false, std::to_string(c.light_count) + " lights of " + std::string(to_string(c.layout)) + " take " +
                     std::to_string(layers) + " layers, above the device's " + std::to_string(max_layers) +
                     " (" + limit + ")"};
}

std::string CaseConfig::id() const {
  std::string id = backend + "/" + scene + "/c" + std::to_string(cube_size) + "/f" + std::to_string(width) +
                   "x" + std::to_string(height) + "/" + std::string(to_string(technique)) + "/" +
                   std::string(to_string(filter)) + "/" + std::string(to_string(storage)) + "/" +
                   std::string(to_string(depth_format));
  if (layout != Layout::cube)
    id += "/" + std::string(to_string(layout));  // cube ids stay as they were before layouts
  if (tessellation != 1) id += "/t" + std::to_string(tessellation);
  if (light_count != 1) id += "/l" + std::to_string(light_count);
  if (light_grouping == LightGrouping::all_lights) id += "/all_lights";
  if (atlas_tiles != AtlasTiles::uniform) id += "/tiles_" + std::string(to_string(atlas_tiles));
  if (shadow_budget_texels) id += "/budget" + std::to_string(shadow_budget_texels);
  if (update_budget_faces) id += "/update" + std::to_string(update_budget_faces);
  if (optimizations.face_culling) id += "/cull";
  if (optimizations.fit_range) id += "/fit";
  if (optimizations.static_cache) id += "/cache";
  if (optimizations.view_culling) id += "/view";
  if (optimizations.light_clusters) id += "/clusters";
  if (pcf_scale != 1.0f) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "/pcf%g", static_cast<double>(pcf_scale));
    id += buf;
  }
  for (const std::string& words : {remedies.any() ? to_string(remedies) : std::string(),
                                   moments.any() ? to_string(moments) : std::string()}) {
    if (words.empty()) continue;  // one segment per word, as for optimisations: /rebase/bias0, /lbr0.5/world
    id += "/" + words;
    std::replace(id.end() - static_cast<std::ptrdiff_t>(words.size()), id.end(), '+', '/');
  }
  if ((emulate_nv_swizzle && technique == Technique::nv_swizzle) ||
      (emulate_mesh_shader && technique == Technique::mesh_shader))
    id += "/emulated";
  if (!experiment.empty()) id += "/" + experiment;
  return id;
}

namespace {
// "a+b+c" -> calls on_word("a"), on_word("b"), on_word("c"): the spelling of optimisation and remedy sets.
template <typename OnWord>
void for_each_plus_word(std::string_view text, OnWord on_word) {
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find('+', start);
    on_word(text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
}

// Every remedy word and how it reads or sets a Remedies, in id order.
struct RemedyWord {
  std::string_view word;
  bool (*is_set)(const Remedies&);
  void (*set)(Remedies&);
};
constexpr RemedyWord kRemedyWords[] = {
    {"rebase", [](const Remedies& r) { return r.rebase_origin; },
     [](Remedies& r) { r.rebase_origin = true; }},
    {"bias0", [](const Remedies& r) { return r.bias == BiasMode::zero; },
     [](Remedies& r) { r.bias = BiasMode::zero; }},
    {"slope_bias", [](const Remedies& r) { return r.bias == BiasMode::slope; },
     [](Remedies& r) { r.bias = BiasMode::slope; }},
    {"normal_offset", [](const Remedies& r) { return r.normal_offset; },
     [](Remedies& r) { r.normal_offset = true; }},
    {"two_sided", [](const Remedies& r) { return r.two_sided; }, [](Remedies& r) { r.two_sided = true; }},
};
}  // namespace

Remedies parse_remedies(std::string_view text) {
  Remedies r;
  if (text == "none") return r;
  for_each_plus_word(text, [&](std::string_view word) {
    const RemedyWord* found = nullptr;
    for (const RemedyWord& w : kRemedyWords)
      if (w.word == word) found = &w;
    if (!found)
      throw std::invalid_argument(
          "unknown remedy '" + std::string(word) +
          "' (valid: none, rebase, bias0, slope_bias, normal_offset, two_sided, or a '+' join)");
    if (r.bias != BiasMode::tutorial && (word == "bias0" || word == "slope_bias"))
      throw std::invalid_argument("bias0 and slope_bias exclude each other");
    found->set(r);
  });
  return r;
}

std::string to_string(const Remedies& r) {
  std::string out;
  for (const RemedyWord& w : kRemedyWords)
    if (w.is_set(r)) out += (out.empty() ? "" : "+") + std::string(w.word);
  return out.empty() ? "none" : out;
}

namespace {
// "lbr0.5" -> 0.5 when `word` starts with `prefix`; nullopt for another word; throws when the number is
// malformed or outside [low, high].
std::optional<float> tuning_number(std::string_view word, std::string_view prefix, float low, float high) {
  if (word.substr(0, prefix.size()) != prefix) return std::nullopt;
  const std::string digits(word.substr(prefix.size()));
  size_t used = 0;
  float v = 0.0f;
  try {
    v = std::stof(digits, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (digits.empty() || used != digits.size() || !(v >= low && v <= high)) {
    char range[64];
    std::snprintf(range, sizeof range, "[%g, %g]", static_cast<double>(low), static_cast<double>(high));
    throw std::invalid_argument("moments tuning '" + std::string(word) + "': " + std::string(prefix) +
                                " takes a number in " + range);
  }
  return v;
}
}  // namespace

MomentsTuning parse_moments_tuning(std::string_view text) {
  MomentsTuning t;
  if (text == "none") return t;
  for_each_plus_word(text, [&](std::string_view word) {
    if (word == "world") {
      t.world_units = true;
    } else if (auto a = tuning_number(word, "lbr", 0.0f, 0.99f)) {
      t.bleed_reduction = *a;
    } else if (auto f = tuning_number(word, "exp", 0.01f, 2.0f)) {
      t.exponent_fraction = *f;
    } else if (auto s = tuning_number(word, "floor", 0.0f, 1e6f)) {
      t.floor_scale = *s;
    } else {
      throw std::invalid_argument(
          "unknown moments tuning '" + std::string(word) +
          "' (valid: none, lbr<a>, exp<f>, floor<s>, world, or a '+' join such as lbr0.4+floor0)");
    }
  });
  return t;
}

std::string to_string(const MomentsTuning& t) {
  const MomentsTuning d;
  std::string out;
  char buf[32];
  auto add = [&](const char* prefix, float v) {
    std::snprintf(buf, sizeof buf, "%s%s%g", out.empty() ? "" : "+", prefix, static_cast<double>(v));
    out += buf;
  };
  if (t.bleed_reduction != d.bleed_reduction) add("lbr", t.bleed_reduction);
  if (t.exponent_fraction != d.exponent_fraction) add("exp", t.exponent_fraction);
  if (t.floor_scale != d.floor_scale) add("floor", t.floor_scale);
  if (t.world_units) out += out.empty() ? "world" : "+world";
  return out.empty() ? "none" : out;
}

Optimizations parse_optimizations(std::string_view text) {
  Optimizations o;
  if (text == "none") return o;
  for_each_plus_word(text, [&](std::string_view word) {
    if (word == "cull")
      o.face_culling = true;
    else if (word == "fit")
      o.fit_range = true;
    else if (word == "cache")
      o.static_cache = true;
    else if (word == "view")
      o.view_culling = true;
    else if (word == "clusters")
      o.light_clusters = true;
    else
      throw std::invalid_argument("unknown optimisation '" + std::string(word) +
                                  "' (valid: none, cull, fit, cache, view, clusters, or a '+' join such as "
                                  "cull+view)");
  });
  return o;
}

std::string to_string(const Optimizations& o) {
  std::string out;
  if (o.face_culling) out += "cull";
  if (o.fit_range) out += std::string(out.empty() ? "" : "+") + "fit";
  if (o.static_cache) out += std::string(out.empty() ? "" : "+") + "cache";
  if (o.view_culling) out += std::string(out.empty() ? "" : "+") + "view";
  if (o.light_clusters) out += std::string(out.empty() ? "" : "+") + "clusters";
  return out.empty() ? "none" : out;
}

}  // namespace omnishadow
