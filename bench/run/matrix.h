#pragma once
// The benchmark matrix: lists per axis, expanded into cases in a fixed order (backend, scene, cube size,
// frame size, storage, depth format, layout, tessellation, light count, filter, ..., technique, light
// grouping). Technique (and the grouping of its lights' passes) is innermost so that each single-pass case
// runs right after the six_pass case it is checked against.

#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "backends/common/case_config.h"

namespace omnishadow::bench {

// --shadow-budget: texels (0: the uniform atlas's), or bytes of shadow storage (a MiB or KiB count), which
// each case turns into texels by its storage's bytes a texel (shadow_bytes_per_texel).
struct ShadowBudget {
  uint64_t amount = 0;
  bool bytes = false;
  bool operator==(const ShadowBudget&) const = default;
};

struct MatrixSpec {
  std::vector<std::string> backends{"gl"};
  std::vector<std::string> scenes{"room", "heavy", "bunny"};  // bunny: a real mesh (scenes/bunny.json)
  std::vector<int> cube_sizes{512, 1024};
  std::vector<std::pair<int, int>> frame_sizes;  // empty: each scene's own camera size
  std::vector<Technique> techniques{Technique::six_pass, Technique::geometry_shader,
                                    Technique::geometry_shader_instanced, Technique::vs_layer,
                                    Technique::multiview};
  std::vector<Filter> filters{Filter::hard, Filter::pcf_grid64, Filter::pcf_disk20};
  std::vector<Storage> storages{Storage::linear_depth};
  std::vector<DepthFormat> depth_formats{DepthFormat::d32f};
  // --layout cube,face_array. Not given (layouts_given false), a scene with a light count above one takes
  // cube_array for all its cases (the cube holds one light only), so that `--scene hall` measures the hall's
  // lamps and its light counts compare in one layout.
  std::vector<Layout> layouts{Layout::cube};
  bool layouts_given = false;
  std::vector<int> tessellations{1};  // --tessellate 1,4,16
  std::vector<int> light_counts;  // --light-count 1,4,16,64; empty: each scene's own number of point lights
  std::vector<LightGrouping> light_groupings{
      LightGrouping::per_light};                             // --light-grouping per_light,all_lights
  std::vector<AtlasTiles> atlas_tiles{AtlasTiles::uniform};  // --atlas-tiles uniform,by_distance (atlas)
  std::vector<ShadowBudget> shadow_budgets{ShadowBudget{}};  // --shadow-budget (atlas by_coverage)
  std::vector<int> atlas_replans{0};          // --atlas-replan frames (0: tiles planned once, at frame 0)
  std::vector<float> atlas_hysteresis{0.0f};  // --atlas-hysteresis octaves (0: none)
  std::vector<int> update_budgets{0};         // --update-budget faces a frame (0: every stale face)
  std::vector<Optimizations> optimizations{Optimizations{}};    // --optimize none,cull,...
  std::vector<Remedies> remedies{Remedies{}};                   // --remedy none,rebase
  std::vector<MomentsTuning> moments_tunings{MomentsTuning{}};  // --moments-tuning none,lbr0.4,exp1.01
  std::vector<float> pcf_scales{1.0f};                          // --pcf-scale 0,1,20
  // Experiment axes (scripts/experiments/sensitivity_same_run.py): extra fragment work per case, and copies
  // of every case measured in the same rounds. Each is in the case id only when it has more than one value
  // (/inj<N>, /rep<k>), so a run with one value keeps the ids of a run without them.
  std::vector<int> injected_work{0};   // --inject-fragment-work 0,18
  int replicas = 1;                    // --replicas 2
  float raster_perturb_steps = 0.0f;   // --raster-perturb 1 (test only: CaseConfig::raster_perturb_steps)
  float lookup_perturb_texels = 0.0f;  // --lookup-perturb 0.05 (test only: CaseConfig::lookup_perturb_texels)
  bool emulate_nv_swizzle = false;     // --emulate-nv-swizzle (test only: CaseConfig::emulate_nv_swizzle)
  bool emulate_mesh_shader = false;    // --emulate-mesh-shader (test only: CaseConfig::emulate_mesh_shader)
  // --technique not given: techniques a backend cannot do at all are left out of its cases (said once on
  // stderr) rather than reported unsupported case by case; a technique asked for by name is always reported.
  bool techniques_given = false;
  // Whether --scene was given: a default scene that cannot load (bunny.json without glmark2-data) is left out
  // with one line, a scene asked for by name is an error.
  bool scenes_given = false;
  // Whether --cube was given. Not given and every backend of the run a CPU driver (llvmpipe, lavapipe): the
  // cube sizes are kCpuDriverCubeSizes, said once on stderr. A CPU driver renders the 1024 cube's fragments
  // on the same two-odd cores as everything else, so those cases cost about half the default run there while
  // telling a GPU user nothing; the first run on such a machine stays about a minute.
  bool cube_sizes_given = false;
  static inline const std::vector<int> kCpuDriverCubeSizes{512};
};

// What the matrix reads of a scene: its camera's frame size (the frame size when spec.frame_sizes is empty)
// and how many point lights it has (the light count when spec.light_counts is empty; 1 for a scene without
// any, whose spot and directional lights every case renders).
struct SceneFacts {
  int width = 0;
  int height = 0;
  int point_lights = 1;
};
std::vector<CaseConfig> expand(const MatrixSpec& spec, const std::map<std::string, SceneFacts>& scenes);

// Deterministic sharding: shard `index` of `count` keeps cases whose position modulo count equals index.
std::vector<CaseConfig> shard(const std::vector<CaseConfig>& cases, int index, int count);

// `--shard auto`: the shard (0-based index, count) from the variables a CI engine or batch system sets, first
// found wins: OMNISHADOW_SHARD_INDEX / OMNISHADOW_SHARD_COUNT (0-based; what our GitHub Actions workflow
// exports from its matrix, GitHub itself numbers nothing), GitLab's CI_NODE_INDEX / CI_NODE_TOTAL
// (`parallel:`, 1-based), Slurm's SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN / SLURM_ARRAY_TASK_COUNT,
// Kubernetes indexed jobs' JOB_COMPLETION_INDEX with OMNISHADOW_SHARD_COUNT (Kubernetes does not export the
// completions). No variables: the whole matrix (0, 1), and `source` says so. Throws std::invalid_argument
// naming a variable that is malformed.
struct ShardFromEnvironment {
  int index = 0;
  int count = 1;
  std::string source;  // "GitLab CI_NODE_INDEX=2 CI_NODE_TOTAL=4", ..., or "none"
};
ShardFromEnvironment shard_from_environment(const std::function<const char*(const char*)>& getenv);

// "256,512" -> {256, 512}; throws std::invalid_argument naming `option` on anything but positive integers,
// each called `what` ("'0' is not a valid size").
std::vector<int> parse_int_list(const std::string& text, const std::string& option,
                                const char* what = "size");
// "800x600,1920x1080"
std::vector<std::pair<int, int>> parse_size_list(const std::string& text, const std::string& option);
std::vector<std::string> split_list(const std::string& text);
// A value given twice would give two cases one id (`--scene room,room`, `--cube 128,128`), which no run can
// tell apart and `compare` refuses: throws std::invalid_argument naming `option` and the value.
template <typename T>
void refuse_repeats(const std::vector<T>& values, const std::vector<std::string>& items,
                    const std::string& option) {
  for (size_t i = 0; i < values.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (values[j] == values[i])
        throw std::invalid_argument(option + ": a value is given twice ('" + items[j] + "' and '" + items[i] +
                                    "')");
}

// "a,b+c" with `parse` applied to each item; errors are prefixed with the option's name.
template <typename Parse>
auto parse_list_with(const std::string& text, const std::string& option, Parse parse) {
  std::vector<decltype(parse(std::string()))> out;
  const std::vector<std::string> items = split_list(text);
  for (const std::string& item : items) {
    try {
      out.push_back(parse(item));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(option + ": " + e.what());
    }
  }
  if (out.empty()) throw std::invalid_argument(option + ": empty list");
  refuse_repeats(items, items, option);  // as written: parsed values of some axes have no ==
  return out;
}

template <typename E>
std::vector<E> parse_enum_list(const std::string& text, const std::string& option) {
  return parse_list_with(text, option, [](const std::string& item) { return parse_enum<E>(item); });
}

}  // namespace omnishadow::bench
