// Matrix expansion: every combination once, in the documented order, split deterministically by --shard.

#include "bench/run/matrix.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include "backends/common/case_support.h"
#include "backends/common/shader_variants.h"

namespace omnishadow::bench {
namespace {

const std::map<std::string, SceneFacts> kSizes = {
    {"room", {800, 600, 1}}, {"heavy", {640, 480, 1}}, {"bunny", {800, 600, 1}}, {"hall", {800, 600, 64}}};

TEST(Matrix, ExpandsEveryCombinationOnceWithTechniqueInnermost) {
  MatrixSpec spec;
  spec.scenes = {"room", "heavy"};
  spec.cube_sizes = {256, 512, 1024};
  auto cases = expand(spec, kSizes);
  EXPECT_EQ(cases.size(), 2u * 3u * 3u * 5u);
  std::set<std::string> ids;
  for (const auto& c : cases) ids.insert(c.id());
  EXPECT_EQ(ids.size(), cases.size());
  EXPECT_EQ(cases[0].id(), "gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f");
  EXPECT_EQ(cases[1].technique, Technique::geometry_shader);
  EXPECT_EQ(cases[5].filter, Filter::pcf_grid64);
  EXPECT_EQ(cases.back().scene, "heavy");
  EXPECT_EQ(cases.back().width, 640);  // the scene's own camera size when --frame is not given
}

// A moments filter stores its own moments: whatever the storage axis names, it runs once, on its storage; the
// lookup filters run on every storage named.
TEST(Matrix, AMomentsFilterRunsOnceOnItsOwnStorage) {
  MatrixSpec spec;
  spec.scenes = {"room"};
  spec.techniques = {Technique::six_pass};
  spec.cube_sizes = {256};
  spec.filters = {Filter::hard, Filter::vsm};
  spec.storages = {Storage::linear_depth, Storage::r32f_distance};
  auto cases = expand(spec, kSizes);
  ASSERT_EQ(cases.size(), 3u);
  std::multiset<Storage> storages;
  for (const auto& c : cases) storages.insert(c.storage);
  EXPECT_EQ(storages.count(Storage::vsm_moments), 1u);
  EXPECT_EQ(cases[1].id(), "gl/room/c256/f800x600/six_pass/vsm/vsm_moments/d32f");
  CaseConfig lookup_on_moments = cases[1];
  lookup_on_moments.filter = Filter::hard;
  EXPECT_FALSE(common_support(lookup_on_moments).ok);
  EXPECT_NE(common_support(lookup_on_moments).reason.find("hard reads a stored distance"), std::string::npos);
}

// A shadow budget in bytes is each case's texels at its storage's bytes a texel: 4 for d32f depth alone, 20
// for vsm (d32f depth, and RG32F moments twice: the map and the blur's intermediate). Only by_coverage keeps
// it.
TEST(Matrix, AShadowBudgetInBytesBecomesEachCasesTexels) {
  MatrixSpec spec;
  spec.scenes = {"hall"};
  spec.light_counts = {16};
  spec.techniques = {Technique::six_pass};
  spec.cube_sizes = {128};
  spec.layouts = {Layout::atlas};
  spec.layouts_given = true;
  spec.filters = {Filter::hard, Filter::vsm};
  spec.atlas_tiles = {AtlasTiles::uniform, AtlasTiles::by_coverage};
  spec.shadow_budgets = {ShadowBudget{1u << 20, true}};
  const auto cases = expand(spec, kSizes);
  std::map<std::string, uint64_t> budgets;
  for (const auto& c : cases)
    budgets[std::string(to_string(c.filter)) + "/" + std::string(to_string(c.atlas_tiles))] =
        c.shadow_budget_texels;
  EXPECT_EQ(budgets.at("hard/by_coverage"), (1u << 20) / 4);
  EXPECT_EQ(budgets.at("vsm/by_coverage"), (1u << 20) / 20);
  EXPECT_EQ(budgets.at("hard/uniform"), 0u) << "a uniform atlas has no budget";
}

// Re-plans move by_distance and by_coverage tiles only: uniform tiles and the other layouts keep one case,
// planned once; the re-planned ids end in /replan<N>, and the support check refuses a re-plan of tiles that
// never change. Hysteresis multiplies the re-planned cases alone, and is refused without re-plans.
TEST(Matrix, AtlasReplansMultiplyOnlyTheTilesTheyMove) {
  MatrixSpec spec;
  spec.scenes = {"hall"};
  spec.light_counts = {16};
  spec.techniques = {Technique::six_pass};
  spec.cube_sizes = {64};
  spec.layouts = {Layout::cube_array, Layout::atlas};
  spec.layouts_given = true;
  spec.atlas_tiles = {AtlasTiles::uniform, AtlasTiles::by_distance};
  spec.atlas_replans = {0, 8};
  spec.atlas_hysteresis = {0.0f, 0.5f};
  spec.filters = {Filter::hard};
  std::multiset<std::string> kinds;
  for (const auto& c : expand(spec, kSizes)) {
    kinds.insert(std::string(to_string(c.layout)) + "/" + std::string(to_string(c.atlas_tiles)) + "/" +
                 std::to_string(c.atlas_replan_frames) + "/" + std::to_string(c.atlas_hysteresis_octaves));
    if (c.atlas_replan_frames) {
      EXPECT_NE(c.id().find("/tiles_by_distance/replan8"), std::string::npos) << c.id();
    }
    EXPECT_EQ(c.id().find("/hysteresis") != std::string::npos, c.atlas_hysteresis_octaves != 0.0f) << c.id();
  }
  // Hysteresis holds sizes between re-plans: only the re-planned case takes both.
  EXPECT_EQ(kinds, (std::multiset<std::string>{"cube_array/uniform/0/0.000000", "atlas/uniform/0/0.000000",
                                               "atlas/by_distance/0/0.000000", "atlas/by_distance/8/0.000000",
                                               "atlas/by_distance/8/0.500000"}));
  CaseConfig uniform;
  uniform.layout = Layout::atlas;
  uniform.light_count = 16;
  uniform.atlas_replan_frames = 8;
  EXPECT_NE(common_support(uniform).reason.find("uniform tiles never change"), std::string::npos);
  uniform.layout = Layout::cube_array;
  EXPECT_NE(common_support(uniform).reason.find("--atlas-replan plans an atlas's tiles again"),
            std::string::npos);
  CaseConfig once;
  once.layout = Layout::atlas;
  once.light_count = 16;
  once.atlas_tiles = AtlasTiles::by_distance;
  once.atlas_hysteresis_octaves = 0.5f;
  EXPECT_NE(
      common_support(once).reason.find("--atlas-hysteresis holds tile sizes from one re-plan to the next"),
      std::string::npos);
  once.atlas_replan_frames = 8;
  EXPECT_TRUE(common_support(once).ok) << common_support(once).reason;
}

// The moments tunings (--moments-tuning): spelling round trip, one id segment per knob away from its default,
// a one-line error naming a bad word, and each knob refused by the filters it means nothing to.
TEST(Matrix, MomentsTuningsParseIntoTheIdAndOnlyTheirFilters) {
  const MomentsTuning t = parse_moments_tuning("lbr0.4+exp1.01+floor0+world");
  EXPECT_FLOAT_EQ(t.bleed_reduction, 0.4f);
  EXPECT_FLOAT_EQ(t.exponent_fraction, 1.01f);
  EXPECT_EQ(t.floor_scale, 0.0f);
  EXPECT_TRUE(t.world_units);
  EXPECT_EQ(to_string(t), "lbr0.4+exp1.01+floor0+world");
  EXPECT_EQ(parse_moments_tuning(to_string(t)), t);
  EXPECT_EQ(to_string(parse_moments_tuning("none")), "none");
  EXPECT_EQ(parse_moments_tuning("exp0.9"), MomentsTuning{}) << "the default exponent is no tuning";
  for (const char* bad : {"lbr1", "lbr", "exp0", "exp2.5", "floor-1", "lbr0.4x", "worlds", "lbr0.4+"}) {
    try {
      parse_moments_tuning(bad);
      ADD_FAILURE() << bad << " parsed";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("moments tuning"), std::string::npos) << e.what();
    }
  }
  MatrixSpec spec;
  spec.scenes = {"room"};
  spec.techniques = {Technique::six_pass};
  spec.cube_sizes = {256};
  spec.filters = {Filter::hard, Filter::vsm, Filter::esm, Filter::msm};
  spec.moments_tunings = {MomentsTuning{}, parse_moments_tuning("lbr0.5+world"),
                          parse_moments_tuning("exp1.01"), parse_moments_tuning("floor0")};
  const auto cases = expand(spec, kSizes);
  ASSERT_EQ(cases.size(), 16u);
  std::map<std::string, bool> supported;
  for (const auto& c : cases) supported[c.id()] = common_support(c).ok;
  EXPECT_TRUE(supported.at("gl/room/c256/f800x600/six_pass/vsm/vsm_moments/d32f/lbr0.5/world"));
  EXPECT_TRUE(supported.at("gl/room/c256/f800x600/six_pass/esm/esm_exp/d32f/exp1.01"));
  EXPECT_TRUE(supported.at("gl/room/c256/f800x600/six_pass/msm/msm_moments/d32f/floor0"));
  EXPECT_TRUE(supported.at("gl/room/c256/f800x600/six_pass/vsm/vsm_moments/d32f/floor0"));
  EXPECT_FALSE(supported.at("gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f/floor0"));
  EXPECT_FALSE(supported.at("gl/room/c256/f800x600/six_pass/esm/esm_exp/d32f/lbr0.5/world"))
      << "esm has no bleeding bound";
  EXPECT_FALSE(supported.at("gl/room/c256/f800x600/six_pass/msm/msm_moments/d32f/lbr0.5/world"))
      << "world is vsm's";
  EXPECT_FALSE(supported.at("gl/room/c256/f800x600/six_pass/vsm/vsm_moments/d32f/exp1.01"));
  EXPECT_EQ(std::count_if(supported.begin(), supported.end(), [](const auto& kv) { return kv.second; }), 8);
}

TEST(Matrix, ExplicitFrameSizesOverrideTheScenes) {
  MatrixSpec spec;
  spec.scenes = {"room"};
  spec.frame_sizes = {{320, 240}, {1920, 1080}};
  auto cases = expand(spec, kSizes);
  EXPECT_EQ(cases.size(), 2u * 2u * 3u * 5u);
  EXPECT_EQ(cases[0].width, 320);
}

// The experiment axes: in the id only with more than one value, so a single injected value keeps the plain
// ids (a run with --inject-fragment-work N compares against one without it).
TEST(Matrix, ExperimentAxesAreInTheIdOnlyWithSeveralValues) {
  MatrixSpec spec;
  spec.scenes = {"room"};
  spec.cube_sizes = {256};
  spec.filters = {Filter::hard};
  spec.techniques = {Technique::six_pass};
  spec.injected_work = {18};
  auto single = expand(spec, kSizes);
  ASSERT_EQ(single.size(), 1u);
  EXPECT_EQ(single[0].id(), "gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f");
  EXPECT_EQ(single[0].injected_work, 18);
  spec.injected_work = {0, 18};
  spec.replicas = 2;
  auto cases = expand(spec, kSizes);
  ASSERT_EQ(cases.size(), 4u);
  EXPECT_EQ(cases[0].id(), "gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f/inj0/rep0");
  EXPECT_EQ(cases[3].id(), "gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f/inj18/rep1");
  EXPECT_EQ(cases[3].injected_work, 18);
  EXPECT_EQ(cases[1].injected_work, 0);
  spec.injected_work = {0};
  EXPECT_EQ(expand(spec, kSizes)[1].id(), "gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f/rep1");
}

// The light-count axis: not given, each scene runs with all of its point lights; given, every scene runs
// each count (more than a scene has is the runner's unsupported). /l<K> in the id above one light only.
TEST(Matrix, LightCountsDefaultToEachScenesOwnAndNameTheirCases) {
  MatrixSpec spec;
  spec.scenes = {"room", "hall"};
  spec.cube_sizes = {256};
  spec.filters = {Filter::hard};
  spec.techniques = {Technique::six_pass};
  auto own = expand(spec, kSizes);
  ASSERT_EQ(own.size(), 2u);
  EXPECT_EQ(own[0].id(), "gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f");
  EXPECT_EQ(own[1].id(), "gl/hall/c256/f800x600/six_pass/hard/linear_depth/d32f/cube_array/l64")
      << "no --layout: a case of several lights takes the layout that holds them";
  EXPECT_EQ(own[1].light_count, 64);
  spec.layouts_given = true;
  EXPECT_EQ(expand(spec, kSizes)[1].layout, Layout::cube) << "a layout asked for by name stays (unsupported)";
  spec.layouts_given = false;
  spec.light_counts = {1, 4};
  spec.filters = {Filter::hard, Filter::pcf_disk20};
  auto cases = expand(spec, kSizes);
  ASSERT_EQ(cases.size(), 8u);
  EXPECT_EQ(cases[1].id(), "gl/room/c256/f800x600/six_pass/pcf_disk20/linear_depth/d32f/cube_array");
  EXPECT_EQ(cases[0].id(), "gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f/cube_array")
      << "one layout for every light count of the scene";
  EXPECT_EQ(cases[2].id(), "gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f/cube_array/l4")
      << "light count outside the filter";
  EXPECT_EQ(cases[4].id(), "gl/hall/c256/f800x600/six_pass/hard/linear_depth/d32f/cube_array");
}

TEST(Matrix, ShardsPartitionTheMatrix) {
  MatrixSpec spec;
  auto cases = expand(spec, kSizes);
  std::multiset<std::string> all;
  for (int i = 0; i < 3; ++i)
    for (const auto& c : shard(cases, i, 3)) all.insert(c.id());
  EXPECT_EQ(all.size(), cases.size());
  std::set<std::string> unique(all.begin(), all.end());
  EXPECT_EQ(unique.size(), cases.size());
  EXPECT_EQ(shard(cases, 1, 3), shard(cases, 1, 3));
  EXPECT_THROW(shard(cases, 3, 3), std::invalid_argument);
}

// --shard auto: each engine's variables and numbering (GitLab 1-based, the others 0-based).
TEST(Matrix, ShardAutoReadsEachEnginesVariables) {
  auto from = [](std::map<std::string, std::string> env) {
    return shard_from_environment([env](const char* name) -> const char* {
      auto it = env.find(name);
      return it == env.end() ? nullptr : it->second.c_str();
    });
  };
  auto gitlab = from({{"CI_NODE_INDEX", "2"}, {"CI_NODE_TOTAL", "4"}});
  EXPECT_EQ(gitlab.index, 1);
  EXPECT_EQ(gitlab.count, 4);
  auto github =
      from({{"OMNISHADOW_SHARD_INDEX", "0"}, {"OMNISHADOW_SHARD_COUNT", "3"}, {"CI_NODE_INDEX", "9"}});
  EXPECT_EQ(github.index, 0);  // ours first: a GitLab job may run our script with its own shard variables too
  EXPECT_EQ(github.count, 3);
  auto slurm =
      from({{"SLURM_ARRAY_TASK_ID", "12"}, {"SLURM_ARRAY_TASK_MIN", "10"}, {"SLURM_ARRAY_TASK_COUNT", "5"}});
  EXPECT_EQ(slurm.index, 2);
  EXPECT_EQ(slurm.count, 5);
  auto k8s = from({{"JOB_COMPLETION_INDEX", "3"}, {"OMNISHADOW_SHARD_COUNT", "8"}});
  EXPECT_EQ(k8s.index, 3);
  EXPECT_EQ(k8s.count, 8);
  auto none = from({});
  EXPECT_EQ(none.count, 1);
  EXPECT_EQ(none.source, "none");
  EXPECT_THROW(from({{"CI_NODE_INDEX", "0"}, {"CI_NODE_TOTAL", "4"}}),
               std::invalid_argument);  // GitLab is 1-based
  EXPECT_THROW(from({{"CI_NODE_INDEX", "5"}, {"CI_NODE_TOTAL", "4"}}), std::invalid_argument);
  EXPECT_THROW(from({{"JOB_COMPLETION_INDEX", "1"}}), std::invalid_argument);  // the count must be given
  try {
    from({{"CI_NODE_INDEX", "two"}, {"CI_NODE_TOTAL", "4"}});
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("CI_NODE_INDEX='two'"), std::string::npos) << e.what();
  }
}

TEST(Matrix, ListParsingNamesTheOptionAndTheValidValues) {
  EXPECT_EQ(parse_int_list("256,512", "--cube"), (std::vector<int>{256, 512}));
  EXPECT_EQ(parse_size_list("800x600", "--frame"), (std::vector<std::pair<int, int>>{{800, 600}}));
  auto message = [](auto fn) {
    try {
      fn();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([] { parse_int_list("0", "--cube"); }).rfind("--cube: '0' is not a valid size", 0), 0u);
  EXPECT_NE(message([] { parse_int_list("512,abc", "--cube"); }).find("'abc'"), std::string::npos);
  EXPECT_NE(message([] { parse_size_list("800", "--frame"); }).find("WIDTHxHEIGHT"), std::string::npos);
  std::string t = message([] { parse_enum_list<Technique>("six_pass,teapot", "--technique"); });
  EXPECT_NE(t.find("--technique: unknown technique 'teapot'"), std::string::npos) << t;
  EXPECT_NE(t.find("valid: six_pass, geometry_shader"), std::string::npos) << t;
  EXPECT_THROW(parse_enum_list<Filter>("", "--filter"), std::invalid_argument);
}

TEST(Matrix, EnumNamesRoundTrip) {
  for (Technique t : all_values<Technique>()) EXPECT_EQ(parse_enum<Technique>(to_string(t)), t);
  for (Filter f : all_values<Filter>()) EXPECT_EQ(parse_enum<Filter>(to_string(f)), f);
  for (Storage s : all_values<Storage>()) EXPECT_EQ(parse_enum<Storage>(to_string(s)), s);
  for (DepthFormat d : all_values<DepthFormat>()) EXPECT_EQ(parse_enum<DepthFormat>(to_string(d)), d);
  for (Layout l : all_values<Layout>()) EXPECT_EQ(parse_enum<Layout>(to_string(l)), l);
}

// The layout axis: a cube case keeps the id it had before layouts existed (baselines and histories
// still match), another layout appends its name after the depth format; each layout's six_pass is its own
// reference, so the equality checks apply within a layout; a bad name is one line naming --layout.
TEST(Matrix, LayoutsExpandIntoTheIdAfterTheDepthFormat) {
  MatrixSpec spec;
  spec.scenes = {"room"};
  spec.cube_sizes = {256};
  spec.filters = {Filter::hard};
  spec.techniques = {Technique::six_pass, Technique::vs_layer};
  spec.layouts = parse_enum_list<Layout>("cube,face_array", "--layout");
  spec.optimizations = {Optimizations{}, parse_optimizations("cull")};
  auto cases = expand(spec, kSizes);
  ASSERT_EQ(cases.size(), 8u);
  EXPECT_EQ(cases[0].id(), "gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f");
  EXPECT_EQ(cases[4].layout, Layout::face_array);
  EXPECT_EQ(cases[4].id(), "gl/room/c256/f800x600/six_pass/hard/linear_depth/d32f/face_array");
  EXPECT_EQ(cases[7].id(), "gl/room/c256/f800x600/vs_layer/hard/linear_depth/d32f/face_array/cull");
  std::string m;
  try {
    parse_enum_list<Layout>("cube,octahedral", "--layout");
  } catch (const std::invalid_argument& e) {
    m = e.what();
  }
  EXPECT_NE(m.find("--layout: unknown layout 'octahedral' (valid: cube, face_array"), std::string::npos) << m;
}

// --atlas-tiles multiplies the atlas's cases only: another layout keeps one case, every light at --cube.
TEST(Matrix, AtlasTilesMultiplyOnlyTheAtlasCases) {
  MatrixSpec spec;
  spec.scenes = {"hall"};
  spec.cube_sizes = {64};
  spec.filters = {Filter::hard};
  spec.layouts = parse_enum_list<Layout>("cube_array,atlas", "--layout");
  spec.layouts_given = true;
  spec.atlas_tiles = parse_enum_list<AtlasTiles>("uniform,by_distance", "--atlas-tiles");
  spec.light_counts = {4};
  spec.techniques = {Technique::six_pass};
  auto cases = expand(spec, kSizes);
  ASSERT_EQ(cases.size(), 3u);
  EXPECT_EQ(cases[0].layout, Layout::cube_array);
  EXPECT_EQ(cases[0].atlas_tiles, AtlasTiles::uniform);
  EXPECT_EQ(cases[1].id(), "gl/hall/c64/f800x600/six_pass/hard/linear_depth/d32f/atlas/l4");
  EXPECT_EQ(cases[2].id(), "gl/hall/c64/f800x600/six_pass/hard/linear_depth/d32f/atlas/l4/tiles_by_distance");
  spec.atlas_tiles = {AtlasTiles::by_distance};  // the only value: cube_array's case stays, uniform
  cases = expand(spec, kSizes);
  ASSERT_EQ(cases.size(), 2u);
  EXPECT_EQ(cases[0].atlas_tiles, AtlasTiles::uniform);
  EXPECT_EQ(cases[1].atlas_tiles, AtlasTiles::by_distance);
}

// Every light in one pass: vs_layer and the geometry shader, the latter up to 64 lights of six cube faces
// each, never with face culling (it culls per light and face already); each refusal names its reason.
TEST(Matrix, EveryLightInOnePassSaysWhereItIsBuilt) {
  CaseConfig c;
  c.scene = "hall";
  c.layout = Layout::cube_array;
  c.light_grouping = LightGrouping::all_lights;
  c.light_count = 64;
  for (Technique t : {Technique::vs_layer, Technique::geometry_shader}) {
    c.technique = t;
    EXPECT_TRUE(common_support(c).ok) << c.id() << ": " << common_support(c).reason;
  }
  auto refused = [](CaseConfig k, const std::string& why) {
    const Support s = common_support(k);
    EXPECT_FALSE(s.ok) << k.id();
    EXPECT_NE(s.reason.find(why), std::string::npos) << s.reason;
  };
  CaseConfig more = c;
  more.light_count = 65;
  refused(more, "reaches 64 lights");
  CaseConfig warped = c;
  warped.layout = Layout::tetrahedral;
  refused(warped, "tetrahedral has layers of its own");
  CaseConfig culled = c;
  culled.optimizations = parse_optimizations("cull");
  refused(culled, "culls per light and face already");
  CaseConfig instanced = c;
  instanced.technique = Technique::geometry_shader_instanced;
  refused(instanced, "geometry_shader_instanced renders per light");
}

// A layout's lookup is a variant of the lighting shader: face_array's define is in its defines and the build
// compiles its SPIR-V for every storage and filter the cube has (the Vulkan backend finds it by the same
// key).
TEST(Matrix, EachLayoutHasItsLightingVariants) {
  CaseConfig c;
  c.layout = Layout::face_array;
  const auto defines = gpu::lighting_defines(c, gpu::LightingVariant::timed);
  EXPECT_EQ(gpu::variant_key("lighting.frag", defines),
            "lighting.frag:STORAGE_LINEAR_DEPTH,FILTER_HARD,LAYOUT_FACE_ARRAY");
  c.layout = Layout::cube;
  EXPECT_EQ(gpu::variant_key("lighting.frag", gpu::lighting_defines(c, gpu::LightingVariant::timed)),
            "lighting.frag:STORAGE_LINEAR_DEPTH,FILTER_HARD");
  const std::vector<std::string> keys = gpu::spirv_variant_keys();
  size_t cube = 0, face_array = 0, paraboloid = 0, tetrahedral = 0, cube_array = 0, atlas = 0, cubes = 0;
  for (const std::string& k : keys) {
    if (k.rfind("lighting.frag:", 0) != 0) continue;
    (k.find("LIGHT_CUBES") != std::string::npos              ? cubes
     : k.find("LAYOUT_FACE_ARRAY") != std::string::npos      ? face_array
     : k.find("LAYOUT_DUAL_PARABOLOID") != std::string::npos ? paraboloid
     : k.find("LAYOUT_TETRAHEDRAL") != std::string::npos     ? tetrahedral
     : k.find("LAYOUT_CUBE_ARRAY") != std::string::npos      ? cube_array
     : k.find("LAYOUT_ATLAS") != std::string::npos           ? atlas
                                                             : cube) += 1;
  }
  EXPECT_GT(cube, 0u);
  EXPECT_EQ(face_array, cube);
  EXPECT_EQ(cube_array, cube) << "a cube-map array reads every storage and filter a cube does";
  // A cube per light (layout cube, several lights): what common_support admits of the cube's (not a compare
  // filter on stored distances, which the single cube's list keeps), and at least the default.
  EXPECT_GT(cubes, 0u);
  EXPECT_LE(cubes, cube);
  EXPECT_EQ(
      std::count(keys.begin(), keys.end(), "lighting.frag:STORAGE_LINEAR_DEPTH,FILTER_HARD,LIGHT_CUBES"), 1);
  // dual_paraboloid and tetrahedral: only what common_support admits (stored distances; no moments filters)
  EXPECT_GT(paraboloid, 0u);
  EXPECT_LT(paraboloid, cube);
  EXPECT_EQ(tetrahedral, paraboloid);
  // atlas: every storage but the moments (their blur runs over layers), every filter that reads one
  EXPECT_GT(atlas, paraboloid);
  EXPECT_LT(atlas, cube);
  for (const std::string& k : keys) {
    if (k.find("LAYOUT_DUAL_PARABOLOID") != std::string::npos ||
        k.find("LAYOUT_TETRAHEDRAL") != std::string::npos) {
      EXPECT_EQ(k.find("MOMENTS"), std::string::npos) << k;
    }
  }
}

}  // namespace
}  // namespace omnishadow::bench
