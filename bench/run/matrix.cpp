#include "bench/run/matrix.h"

#include <stdexcept>

#include "backends/common/storage_filter_tables.h"

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

std::vector<int> parse_int_list(const std::string& text, const std::string& option) {
  std::vector<int> out;
  const std::vector<std::string> items = split_list(text);
  for (const std::string& item : items) out.push_back(parse_positive(item, option, "size"));
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

std::vector<CaseConfig> expand(const MatrixSpec& spec,
                               const std::map<std::string, std::pair<int, int>>& scene_sizes) {
  std::vector<CaseConfig> cases;
  for (const auto& backend : spec.backends)
    for (const auto& scene : spec.scenes) {
      std::vector<std::pair<int, int>> sizes = spec.frame_sizes;
      if (sizes.empty()) {
        auto it = scene_sizes.find(scene);
        if (it == scene_sizes.end()) throw std::invalid_argument("no frame size known for scene " + scene);
        sizes.push_back(it->second);
      }
      for (int cube : spec.cube_sizes)
        for (const auto& [w, h] : sizes)
          for (Storage storage : spec.storages)
            for (DepthFormat depth : spec.depth_formats)
              for (Layout layout : spec.layouts)
                for (int tessellation : spec.tessellations)
                  for (Filter filter : spec.filters)
                    for (float pcf_scale : spec.pcf_scales)
                      for (const Remedies& remedies : spec.remedies)
                        for (const MomentsTuning& moments : spec.moments_tunings)
                          for (const Optimizations& optimizations : spec.optimizations)
                            for (Technique technique : spec.techniques)
                              for (int injected : spec.injected_work)
                                for (int replica = 0; replica < spec.replicas; ++replica) {
                                  // A moments filter stores its own moments whatever the storage axis says:
                                  // one case, not one per storage named.
                                  if (traits(filter).own_storage && storage != spec.storages.front())
                                    continue;
                                  CaseConfig c;
                                  c.injected_work = injected;
                                  if (spec.injected_work.size() > 1)
                                    c.experiment = "inj" + std::to_string(injected);
                                  if (spec.replicas > 1)
                                    c.experiment +=
                                        (c.experiment.empty() ? "rep" : "/rep") + std::to_string(replica);
                                  c.backend = backend;
                                  c.scene = scene;
                                  c.cube_size = cube;
                                  c.width = w;
                                  c.height = h;
                                  c.storage = storage_for(filter, storage);
                                  c.depth_format = depth;
                                  c.layout = layout;
                                  c.tessellation = tessellation;
                                  c.filter = filter;
                                  c.technique = technique;
                                  c.optimizations = optimizations;
                                  c.remedies = remedies;
                                  c.moments = moments;
                                  c.pcf_scale = pcf_scale;
                                  c.raster_perturb_steps = spec.raster_perturb_steps;
                                  c.lookup_perturb_texels = spec.lookup_perturb_texels;
                                  c.emulate_nv_swizzle = spec.emulate_nv_swizzle;
                                  cases.push_back(c);
                                }
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
