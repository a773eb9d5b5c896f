#include "bench/run/matrix.h"

#include <algorithm>
#include <stdexcept>
#include <tuple>

#include "backends/common/storage_filter_tables.h"
#include "bench/run/memory_budget.h"

namespace omnishadow::bench {

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= text.size()) {
    size_t comma = text.find(',', start);
    if (comma == std::string::npos) comma = text.size();
    std::string item = text.substr(start, comma - start);
    if (!item.empty()) out.push_back(item);
    start = comma + 1;
  }
  return out;
}

namespace {

int parse_positive(const std::string& item, const std::string& option, const char* what) {
  size_t used = 0;
  long value = 0;
  try {
    value = std::stol(item, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != item.size() || item.empty() || value < 1 || value > (1 << 20))
    throw std::invalid_argument(option + ": '" + item + "' is not a valid " + what +
                                " (a whole number from 1 to 1048576)");
  return static_cast<int>(value);
}

}  // namespace

std::vector<int> parse_int_list(const std::string& text, const std::string& option, const char* what) {
  std::vector<int> out;
  const std::vector<std::string> items = split_list(text);
  for (const std::string& item : items) out.push_back(parse_positive(item, option, what));
  if (out.empty()) throw std::invalid_argument(option + ": empty list");
  refuse_repeats(out, items, option);
  return out;
}

std::vector<std::pair<int, int>> parse_size_list(const std::string& text, const std::string& option) {
  std::vector<std::pair<int, int>> out;
  const std::vector<std::string> items = split_list(text);
  for (const std::string& item : items) {
    size_t x = item.find('x');
    if (x == std::string::npos) throw std::invalid_argument(option + ": '" + item + "' is not WIDTHxHEIGHT");
    out.emplace_back(parse_positive(item.substr(0, x), option, "width"),
                     parse_positive(item.substr(x + 1), option, "height"));
  }
  if (out.empty()) throw std::invalid_argument(option + ": empty list");
  refuse_repeats(out, items, option);
  return out;
}

namespace {

// Every case of `cases` once per value of an axis, the axis inside the ones before it: expanding the axes
// outermost first gives the documented order.
template <typename T, typename Set>
void times(std::vector<CaseConfig>& cases, const std::vector<T>& values, Set set) {
  std::vector<CaseConfig> out;
  out.reserve(cases.size() * values.size());
  for (const CaseConfig& c : cases)
    for (const T& v : values) {
      out.push_back(c);
      set(out.back(), v);
    }
  cases = std::move(out);
}

// One scene's cases on one backend, in the order of the loops matrix.h documents.
std::vector<CaseConfig> scene_cases(const MatrixSpec& spec, const CaseConfig& base, const SceneFacts& facts) {
  std::vector<CaseConfig> cases{base};
  std::vector<std::pair<int, int>> sizes = spec.frame_sizes;
  if (sizes.empty()) sizes.emplace_back(facts.width, facts.height);
  std::vector<int> light_counts = spec.light_counts;
  if (light_counts.empty()) light_counts.push_back(std::max(facts.point_lights, 1));
  times(cases, spec.cube_sizes, [](CaseConfig& c, int v) { c.cube_size = v; });
  times(cases, sizes, [](CaseConfig& c, const std::pair<int, int>& v) { std::tie(c.width, c.height) = v; });
  times(cases, spec.storages, [](CaseConfig& c, Storage v) { c.storage = v; });
  times(cases, spec.depth_formats, [](CaseConfig& c, DepthFormat v) { c.depth_format = v; });
  // No --layout and a case of several lights: the scene's cases take the layout that holds them, all of them
  // so that its light counts compare in one layout.
  const bool many = std::any_of(light_counts.begin(), light_counts.end(), [](int k) { return k > 1; });
  const std::vector<Layout> layouts =
      !spec.layouts_given && many ? std::vector<Layout>{Layout::cube_array} : spec.layouts;
  times(cases, layouts, [](CaseConfig& c, Layout v) { c.layout = v; });
  times(cases, spec.tessellations, [](CaseConfig& c, int v) { c.tessellation = v; });
  times(cases, light_counts, [](CaseConfig& c, int v) { c.light_count = v; });
  times(cases, spec.filters, [](CaseConfig& c, Filter v) { c.filter = v; });
  // A moments filter stores its own moments whatever the storage axis says: one case, not one per storage.
  std::erase_if(cases, [&](const CaseConfig& c) {
    return traits(c.filter).own_storage && c.storage != spec.storages.front();
  });
  for (CaseConfig& c : cases) c.storage = storage_for(c.filter, c.storage);
  times(cases, spec.pcf_scales, [](CaseConfig& c, float v) { c.pcf_scale = v; });
  times(cases, spec.remedies, [](CaseConfig& c, const Remedies& v) { c.remedies = v; });
  times(cases, spec.moments_tunings, [](CaseConfig& c, const MomentsTuning& v) { c.moments = v; });
  times(cases, spec.optimizations, [](CaseConfig& c, const Optimizations& v) { c.optimizations = v; });
  times(cases, spec.techniques, [](CaseConfig& c, Technique v) { c.technique = v; });
  times(cases, spec.light_groupings, [](CaseConfig& c, LightGrouping v) { c.light_grouping = v; });
  // Tile sizes are the atlas's own: the other layouts keep one case (every light at --cube).
  times(cases, spec.atlas_tiles, [](CaseConfig& c, AtlasTiles v) { c.atlas_tiles = v; });
  std::erase_if(cases, [&](const CaseConfig& c) {
    return c.layout != Layout::atlas && c.atlas_tiles != spec.atlas_tiles.front();
  });
  for (CaseConfig& c : cases)
    if (c.layout != Layout::atlas) c.atlas_tiles = AtlasTiles::uniform;
  // A budget sizes by_coverage tiles only: the other cases keep one, without a budget.
  times(cases, spec.shadow_budgets, [](CaseConfig& c, const ShadowBudget& v) {
    c.shadow_budget_texels = v.bytes ? std::max<uint64_t>(v.amount / shadow_bytes_per_texel(c), 1) : v.amount;
  });
  std::erase_if(cases, [&](const CaseConfig& c) {
    const ShadowBudget& first = spec.shadow_budgets.front();
    const uint64_t first_texels =
        first.bytes ? std::max<uint64_t>(first.amount / shadow_bytes_per_texel(c), 1) : first.amount;
    return c.atlas_tiles != AtlasTiles::by_coverage && c.shadow_budget_texels != first_texels;
  });
  for (CaseConfig& c : cases)
    if (c.atlas_tiles != AtlasTiles::by_coverage) c.shadow_budget_texels = 0;
  // Re-plans move by_distance and by_coverage tiles only: the other cases keep one, planned once.
  times(cases, spec.atlas_replans, [](CaseConfig& c, int v) { c.atlas_replan_frames = v; });
  std::erase_if(cases, [&](const CaseConfig& c) {
    return (c.layout != Layout::atlas || c.atlas_tiles == AtlasTiles::uniform) &&
           c.atlas_replan_frames != spec.atlas_replans.front();
  });
  for (CaseConfig& c : cases)
    if (c.layout != Layout::atlas || c.atlas_tiles == AtlasTiles::uniform) c.atlas_replan_frames = 0;
  // Hysteresis holds sizes between re-plans: a case planned once keeps one.
  times(cases, spec.atlas_hysteresis, [](CaseConfig& c, float v) { c.atlas_hysteresis_octaves = v; });
  std::erase_if(cases, [&](const CaseConfig& c) {
    return !c.atlas_replan_frames && c.atlas_hysteresis_octaves != spec.atlas_hysteresis.front();
  });
  for (CaseConfig& c : cases)
    if (!c.atlas_replan_frames) c.atlas_hysteresis_octaves = 0.0f;
  times(cases, spec.update_budgets, [](CaseConfig& c, int v) { c.update_budget_faces = v; });
  times(cases, spec.injected_work, [&](CaseConfig& c, int v) {
    c.injected_work = v;
    if (spec.injected_work.size() > 1) c.experiment = "inj" + std::to_string(v);
  });
  std::vector<int> replicas(size_t(std::max(spec.replicas, 1)));
  for (size_t k = 0; k < replicas.size(); ++k) replicas[k] = int(k);
  times(cases, replicas, [&](CaseConfig& c, int k) {
    if (spec.replicas > 1) c.experiment += (c.experiment.empty() ? "rep" : "/rep") + std::to_string(k);
  });
  return cases;
}

}  // namespace

std::vector<CaseConfig> expand(const MatrixSpec& spec, const std::map<std::string, SceneFacts>& scenes) {
  std::vector<CaseConfig> cases;
  for (const auto& backend : spec.backends)
    for (const auto& scene : spec.scenes) {
      auto facts = scenes.find(scene);
      if (facts == scenes.end()) throw std::invalid_argument("nothing known of scene " + scene);
      CaseConfig base;
      base.backend = backend;
      base.scene = scene;
      base.raster_perturb_steps = spec.raster_perturb_steps;
      base.lookup_perturb_texels = spec.lookup_perturb_texels;
      base.emulate_nv_swizzle = spec.emulate_nv_swizzle;
      base.emulate_mesh_shader = spec.emulate_mesh_shader;
      std::vector<CaseConfig> more = scene_cases(spec, base, facts->second);
      cases.insert(cases.end(), more.begin(), more.end());
    }
  return cases;
}

std::vector<CaseConfig> shard(const std::vector<CaseConfig>& cases, int index, int count) {
  if (count < 1 || index < 0 || index >= count)
    throw std::invalid_argument("--shard: expected i/N with 0 <= i < N");
  std::vector<CaseConfig> out;
  for (size_t i = 0; i < cases.size(); ++i)
    if (static_cast<int>(i % static_cast<size_t>(count)) == index) out.push_back(cases[i]);
  return out;
}

namespace {

int env_int(const std::function<const char*(const char*)>& getenv, const char* name, int min) {
  const char* text = getenv(name);
  std::string value = text ? text : "";
  size_t used = 0;
  int v = min - 1;
  try {
    v = std::stoi(value, &used);
  } catch (const std::exception&) {
  }
  if (value.empty() || used != value.size() || v < min)
    throw std::invalid_argument(std::string("--shard auto: ") + name + "='" + value +
                                "' is not an integer >= " + std::to_string(min));
  return v;
}

}  // namespace

ShardFromEnvironment shard_from_environment(const std::function<const char*(const char*)>& getenv) {
  auto has = [&](const char* name) { return getenv(name) != nullptr; };
  ShardFromEnvironment s;
  if (has("OMNISHADOW_SHARD_INDEX")) {
    s = {env_int(getenv, "OMNISHADOW_SHARD_INDEX", 0), env_int(getenv, "OMNISHADOW_SHARD_COUNT", 1),
         "OMNISHADOW_SHARD_INDEX"};
  } else if (has("CI_NODE_INDEX")) {
    s = {env_int(getenv, "CI_NODE_INDEX", 1) - 1, env_int(getenv, "CI_NODE_TOTAL", 1),
         "GitLab CI_NODE_INDEX"};
  } else if (has("SLURM_ARRAY_TASK_ID")) {
    int min = has("SLURM_ARRAY_TASK_MIN") ? env_int(getenv, "SLURM_ARRAY_TASK_MIN", 0) : 0;
    s = {env_int(getenv, "SLURM_ARRAY_TASK_ID", 0) - min, env_int(getenv, "SLURM_ARRAY_TASK_COUNT", 1),
         "Slurm SLURM_ARRAY_TASK_ID"};
  } else if (has("JOB_COMPLETION_INDEX")) {
    s = {env_int(getenv, "JOB_COMPLETION_INDEX", 0), env_int(getenv, "OMNISHADOW_SHARD_COUNT", 1),
         "Kubernetes JOB_COMPLETION_INDEX"};
  } else {
    return {0, 1, "none"};
  }
  if (s.index < 0 || s.index >= s.count)
    throw std::invalid_argument("--shard auto: " + s.source + " gives shard " + std::to_string(s.index) +
                                " of " + std::to_string(s.count) + " (0-based): out of range");
  s.source += " -> shard " + std::to_string(s.index) + "/" + std::to_string(s.count);
  return s;
}

}  // namespace omnishadow::bench
