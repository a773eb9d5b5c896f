#include "backends/common/case_config.h"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "backends/common/layouts.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"

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

bool light_cubes(const CaseConfig& c) { return c.layout == Layout::cube && c.light_count > 1; }

std::string CaseConfig::atlas_tiling_id() const {
  std::string id;
  if (atlas_tiles != AtlasTiles::uniform) id += "/tiles_" + std::string(to_string(atlas_tiles));
  if (shadow_budget_texels) id += "/budget" + std::to_string(shadow_budget_texels);
  if (atlas_replan_frames) id += "/replan" + std::to_string(atlas_replan_frames);
  if (atlas_hysteresis_octaves != 0.0f) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "/hysteresis%g", static_cast<double>(atlas_hysteresis_octaves));
    id += buf;
  }
  return id;
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
  id += atlas_tiling_id();
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
