#include "bench/cli/matrix_options.h"

#include <stdexcept>
#include <string>
#include <vector>

#include "bench/cli/cli_options.h"

namespace omnishadow::bench {
namespace {

template <typename T, typename Name>
std::string join(const std::vector<T>& values, Name name) {
  std::string out;
  for (const T& v : values) out += (out.empty() ? "" : ",") + std::string(name(v));
  return out;
}

// A comma-list option parsed into `target` when given; its default shown is `target`'s initial value (the
// defaults live in MatrixSpec alone).
template <typename T, typename Parse, typename Name>
void list_option(CLI::App& sub, const std::string& flag, std::vector<T>& target, Parse parse, Name name,
                 const std::string& help) {
  sub.add_option_function<std::string>(
         flag,
         [&target, parse, flag](const std::string& text) { target = parse_list_with(text, flag, parse); },
         help)
      ->default_str(join(target, name));
}

float parse_pcf_scale(const std::string& t) {
  size_t used = 0;
  float v = -1.0f;
  try {
    v = std::stof(t, &used);
  } catch (const std::exception&) {
  }
  if (used != t.size() || !(v >= 0.0f && v <= 100.0f))
    throw std::invalid_argument("'" + t + "' is not a scale in [0, 100]");
  return v;
}

// A texel count: digits, optionally K or M (2^10, 2^20 texels): "4M" is 4194304. 0: the uniform atlas's.
// Texels ("4M" = 4194304, "256K") or bytes of shadow storage ("64MiB", "512KiB").
ShadowBudget parse_shadow_budget(const std::string& t) {
  const size_t digits = t.find_first_not_of("0123456789");
  const std::string number = t.substr(0, digits),
                    suffix = digits == std::string::npos ? "" : t.substr(digits);
  const bool bytes = suffix == "KiB" || suffix == "MiB";
  const int shift = suffix.empty()                     ? 0
                    : suffix == "K" || suffix == "KiB" ? 10
                    : suffix == "M" || suffix == "MiB" ? 20
                                                       : -1;
  if (number.empty() || number.size() > 12 || shift < 0)
    throw std::invalid_argument("'" + t +
                                "' is not a texel count (digits, optionally K or M) or a size (KiB, MiB)");
  if (bytes && std::stoull(number) == 0)
    throw std::invalid_argument("'" + t + "': a budget in bytes must be above 0");
  return {std::stoull(number) << shift, bytes};
}

// "none" (0) or a positive count of `what`.
int parse_none_or_count(const std::string& t, const std::string& what) {
  if (t == "none") return 0;
  const bool digits = !t.empty() && t.size() <= 6 && t.find_first_not_of("0123456789") == std::string::npos;
  if (!digits || std::stoi(t) < 1)
    throw std::invalid_argument("'" + t + "' is not " + what + " (none, or a whole number from 1 to 999999)");
  return std::stoi(t);
}
// The update budget: none, every stale face each frame.
int parse_face_budget(const std::string& t) { return parse_none_or_count(t, "a face count"); }
// Atlas re-plans: none, the tiles planned once.
int parse_replan_frames(const std::string& t) { return parse_none_or_count(t, "a frame interval"); }

// Atlas hysteresis: none (0), or octaves in (0, 3] (by_distance has four sizes, three octaves apart).
float parse_hysteresis_octaves(const std::string& t) {
  if (t == "none") return 0.0f;
  size_t used = 0;
  float v = -1.0f;
  try {
    v = std::stof(t, &used);
  } catch (const std::exception&) {
  }
  if (used != t.size() || !(v > 0.0f && v <= 3.0f))
    throw std::invalid_argument("'" + t + "' is not a hysteresis (none, or octaves above 0 and at most 3)");
  return v;
}

// The axes that say what is drawn and at what size: backends, scenes, cube and frame sizes.
void add_scene_axes(CLI::App& r, MatrixSpec& m) {
  auto text = [](const std::string& s) { return s; };
  auto same = [](const std::string& s) { return s; };
  list_option(r, "--backend", m.backends, same, text, "comma list of backends: gl, vulkan");
  r.add_option_function<std::string>(
       "--scene",
       [&m, same](const std::string& t) {
         m.scenes = parse_list_with(t, "--scene", same);
         m.scenes_given = true;
       },
       "comma list of scene names (scenes/<name>.json), scene file paths, or model files (.glb, .gltf, .obj: "
       "floor, light and camera placed by rule, docs/guide.md \"Your own model\"); case ids name a file by "
       "its stem")
      ->default_str(join(m.scenes, text));
  r.add_option_function<std::string>(
       "--cube",
       [&m](const std::string& t) {
         m.cube_sizes = parse_int_list(t, "--cube");
         m.cube_sizes_given = true;
       },
       "comma list of cube face sizes in texels (default on a run whose every backend is a CPU driver: " +
           join(MatrixSpec::kCpuDriverCubeSizes, [](int v) { return std::to_string(v); }) + ")")
      ->default_str(join(m.cube_sizes, [](int v) { return std::to_string(v); }));
  r.add_option_function<std::string>(
      "--frame", [&m](const std::string& t) { m.frame_sizes = parse_size_list(t, "--frame"); },
      "comma list of WIDTHxHEIGHT (default: each scene's camera size)");
}

// The point lights' axes: how many of a scene's lights a case renders, and how their shadow passes are
// grouped.
void add_light_axes(CLI::App& r, MatrixSpec& m) {
  auto named = [](auto v) { return std::string(to_string(v)); };
  r.add_option_function<std::string>(
       "--light-count",
       [&m](const std::string& t) {
         m.light_counts = parse_int_list(t, "--light-count", "light count");
         for (int n : m.light_counts)
           if (n > scene::kMaxPointLights)
             throw std::invalid_argument("--light-count: " + std::to_string(n) + " is more than " +
                                         std::to_string(scene::kMaxPointLights) + " lights");
       },
       "comma list of point-light counts: each case renders the scene's first K point lights (ids end in "
       "/l<K> above 1); a scene with fewer says unsupported")
      ->default_str("each scene's own");
  list_option(
      r, "--light-grouping", m.light_groupings,
      [](const std::string& s) { return parse_enum<LightGrouping>(s); }, named,
      "comma list: " + valid_values<LightGrouping>() +
          " (how the point lights' shadow passes are grouped: each light in its own passes, or every "
          "light in one pass, vs_layer's instance per light and face, the geometry shader's invocations "
          "per light or mesh_shader's task workgroups per meshlet group and light; ids end in /all_lights "
          "for the second)");
  list_option(
      r, "--atlas-tiles", m.atlas_tiles, [](const std::string& s) { return parse_enum<AtlasTiles>(s); },
      named,
      "comma list: " + valid_values<AtlasTiles>() +
          " (layout atlas: every light's faces at --cube, --cube halved once per doubling of the "
          "light's distance from the camera over its range (at most three times), or by its range's "
          "screen coverage within --shadow-budget; ids end in /tiles_<tiling> but for uniform; other "
          "layouts ignore it)");
  list_option(
      r, "--shadow-budget", m.shadow_budgets, parse_shadow_budget,
      [](const ShadowBudget& v) { return std::to_string(v.amount) + (v.bytes ? " bytes" : ""); },
      "comma list of texel counts (4M = 4194304; 0: the uniform atlas's texels) or sizes of shadow storage "
      "(64MiB, 512KiB: each case's texels are the size over its storage's bytes a texel), for --atlas-tiles "
      "by_coverage: each light's faces by the screen area its range covers, the largest that fit the atlas "
      "in "
      "the budget; ids end in /budget<texels> when not 0; other tilings ignore it");
  list_option(
      r, "--atlas-replan", m.atlas_replans, parse_replan_frames,
      [](int v) { return v ? std::to_string(v) : std::string("none"); },
      "comma list of frame intervals (none: the tiles planned once, from frame 0) for --atlas-tiles "
      "by_distance and by_coverage: every this many frames the tiles are sized again from that frame's "
      "camera and lights and packed into the atlas as allocated, and a light whose tile moved renders "
      "again; ids end in /replan<frames>; other tilings ignore it");
  list_option(
      r, "--atlas-hysteresis", m.atlas_hysteresis, parse_hysteresis_octaves,
      [](float v) { return v != 0.0f ? std::to_string(v) : std::string("none"); },
      "comma list of octaves (none, or above 0 and at most 3) for --atlas-replan: at a re-plan a light keeps "
      "its tiles' size while its tiling gives that size for a distance or coverage within a factor 2^octaves "
      "of the light's own, so that a light near a size's edge is not resized (and rendered whole) back and "
      "forth; ids end in /hysteresis<octaves>; cases planned once ignore it");
  list_option(
      r, "--update-budget", m.update_budgets, parse_face_budget,
      [](int v) { return v ? std::to_string(v) : std::string("none"); },
      "comma list of cube faces rendered at most a frame (none: every stale face): the faces whose light "
      "moved since they were rendered, oldest first, the others keep what they hold; such a case also runs "
      "a sequence of frames for the error its stale faces cost (--staleness-frames); ids end in "
      "/update<faces>");
}

// The axes that say how it is drawn: technique, filter, storage, layout and what tunes them.
void add_technique_axes(CLI::App& r, MatrixSpec& m) {
  auto named = [](auto v) { return std::string(to_string(v)); };
  r.add_option_function<std::string>(
       "--technique",
       [&m](const std::string& t) {
         m.techniques = parse_enum_list<Technique>(t, "--technique");
         m.techniques_given = true;
       },
       "comma list: " + valid_values<Technique>() +
           " (default: every technique the backend can do; one asked for by name is reported unsupported)")
      ->default_str(join(m.techniques, named));
  list_option(
      r, "--filter", m.filters, [](const std::string& s) { return parse_enum<Filter>(s); }, named,
      "comma list: " + valid_values<Filter>());
  list_option(
      r, "--storage", m.storages, [](const std::string& s) { return parse_enum<Storage>(s); }, named,
      "comma list: " + valid_values<Storage>());
  list_option(
      r, "--depth-format", m.depth_formats, [](const std::string& s) { return parse_enum<DepthFormat>(s); },
      named, "comma list: " + valid_values<DepthFormat>());
  list_option(
      r, "--layout", m.layouts,
      [&m](const std::string& s) {
        m.layouts_given = true;
        return parse_enum<Layout>(s);
      },
      named,
      "comma list: " + valid_values<Layout>() +
          " (how the lights' depth is stored and looked up: a cube map, its six faces as a 2D array "
          "whose layer the shader picks, two paraboloids warped per vertex or four tetrahedral faces, "
          "sized to the cube's memory, every light's cube in one cube-map array, or every light's faces as "
          "bordered tiles of one 2D texture (atlas); not given: cube, and "
          "cube_array for a scene run with more than one point light)");
  r.add_option_function<std::string>(
       "--tessellate",
       [&m](const std::string& t) {
         m.tessellations = parse_int_list(t, "--tessellate", "subdivision");
         for (int n : m.tessellations)
           if (n > 64)
             throw std::invalid_argument("--tessellate: " + std::to_string(n) + " is more than 64 a side");
       },
       "comma list of subdivisions, 1 to 64: every triangle split into n^2 (1 = as loaded; the same surfaces "
       "in "
       "smaller triangles, for a layout whose warp bends edges: dual_paraboloid)")
      ->default_str(join(m.tessellations, [](int v) { return std::to_string(v); }));
  list_option(
      r, "--optimize", m.optimizations, [](const std::string& s) { return parse_optimizations(s); },
      [](const Optimizations& o) { return to_string(o); },
      "comma list of optimisation sets, each none or a '+' join of cull (per-face culling, empty faces "
      "cleared only), fit (far plane fitted to the scene), cache (static cube not re-rendered), view (a "
      "light "
      "whose range misses the camera's view gets no pass, a face no visible point's lookup reads none), "
      "clusters (each pixel shaded with its cluster's lights, lists built each frame): --optimize none,cull "
      "measures culling on and off");
  list_option(
      r, "--remedy", m.remedies, [](const std::string& s) { return parse_remedies(s); },
      [](const Remedies& o) { return to_string(o); },
      "comma list of numerical remedies, each none or a '+' join of rebase (scene loaded relative to its "
      "light in double precision), bias0, slope_bias (max(0.05 (1 - n.l), 0.005), docs/glossary.md), "
      "normal_offset (lookup 1.5 texels along the normal), two_sided (casters without back-face culling)");
  list_option(
      r, "--moments-tuning", m.moments_tunings, [](const std::string& s) { return parse_moments_tuning(s); },
      [](const MomentsTuning& t) { return to_string(t); },
      "comma list of moments-filter tunings, each none or a '+' join of lbr<a> (light-bleeding reduction, "
      "vsm/evsm/msm), exp<f> (esm/evsm exponent as a fraction of the format's overflow limit; default 0.9), "
      "floor<s> (vsm variance floor / msm moment bias times s), world (vsm in world units)");
  list_option(
      r, "--pcf-scale", m.pcf_scales, parse_pcf_scale, [](float v) { return std::to_string(int(v)); },
      "comma list of PCF radius scales (0 to 100; 1 = the reference kernels, 0 = one direction)");
}

}  // namespace

void add_matrix_options(CLI::App& r, MatrixSpec& m) {
  add_scene_axes(r, m);
  add_technique_axes(r, m);
  add_light_axes(r, m);
}

}  // namespace omnishadow::bench
