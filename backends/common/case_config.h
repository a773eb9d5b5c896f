#pragma once
// The axes of a benchmark case and their spellings. Names here are the spellings used on the command line, in
// case ids and in results JSON; parse_* accept exactly these. The tutorials the comments name are in
// docs/glossary.md.

#include <string>
#include <string_view>
#include <vector>

namespace omnishadow {

enum class Technique {
  six_pass,         // one render pass per face, each into a prebuilt per-face framebuffer
  geometry_shader,  // one layered pass; the GS loops over 6 faces (the point-shadow tutorial's form, 18
                    // vertices out)
  geometry_shader_instanced,  // one layered pass; GS invocations = 6, one face per invocation
  vs_layer,                   // one layered pass; 6 instances, gl_Layer written by the vertex shader
  multiview,                  // one pass with a 6-view mask; gl_ViewIndex picks the face (Vulkan)
  nv_swizzle,   // one pass; a passthrough GS sends each triangle to six viewports whose swizzles permute
                // the light-relative position into each face's clip space (NVIDIA's cube-map path:
                // GL/VK_NV_viewport_swizzle, NV_viewport_array2, NV_geometry_shader_passthrough)
  mesh_shader,  // one pass of task + mesh shaders over meshlets: the task stage culls each meshlet
                // against the six faces, the mesh stage emits it once per face (gl_Layer per primitive)
};
enum class Filter {
  hard,           // one lookup, bias 0.05 (the point-shadow tutorial)
  pcf_grid64,     // 4x4x4 offsets of +-0.1 around the direction, bias 0.05 (the point-shadow tutorial)
  pcf_disk20,     // 20 directions, radius (1 + viewDistance/far)/25, bias 0.15 (the point-shadow tutorial)
  hw_compare2x2,  // samplerCubeShadow with LINEAR compare: the hardware's 2x2 bilinear PCF; bias 0.05
  pcss,  // percentage-closer soft shadows (Fernando 2005): a blocker search, then the 20-direction disk sized
         // by the penumbra of a spherical light of kPcssLightRadius (times --pcf-scale); bias 0.15
  vsm,   // variance shadow maps (Donnelly & Lauritzen 2006): blurred moments (z, z^2) of z = distance / far,
         // Chebyshev's upper bound on the lit fraction (shaders/moments.glsl); storage vsm_moments
  esm,   // exponential shadow maps (Annen et al. 2008): the blurred exp(c z), lit = exp(c z) e^(-c t)
         // clamped to 1, c from the storage format's range; storage esm_exp
  evsm2,  // exponential variance shadow maps (Lauritzen & McCool 2008), positive warp: VSM's Chebyshev bound
          // on the blurred (e^(cz), e^(2cz)); storage evsm2_moments
  evsm4,  // EVSM with both warps: the lesser of the bounds on (e^(cz), e^(2cz)) and (-e^(-cz), e^(-2cz));
          // storage evsm4_moments
  msm,    // moment shadow maps (Peters & Klein 2015), Hamburger 4MSM: (z, z^2, z^3, z^4) biased towards
          // (0.5, 0.5, 0.5, 0.5), the sharpest occlusion bound they allow; storage msm_moments
};
// The light PCSS imitates: the soft reference's default --light-radius, so that mae_sphere scores it against
// the light it models (world units).
inline constexpr float kPcssLightRadius = 0.1f;
enum class Storage {
  linear_depth,   // the point-shadow tutorial: gl_FragDepth = distance / far in a depth cube map
  r32f_distance,  // the multipass tutorial: distance in an R32F colour cube (cleared to FLT_MAX) + a separate
                  // depth cube
  hardware_depth,  // the rasteriser's own (non-linear, projective) depth, no fragment write; the lookup
                   // converts it back to a distance along the sampled direction
  vsm_moments,     // linear_depth's depth plus (z, z^2) of z = distance / far in an RG32F colour cube (RG16F
                   // with d16), blurred before the lighting pass: the vsm filter's storage
  esm_exp,  // linear_depth's depth plus exp(c min(z, 1)) in an R32F colour cube (R16F with d16), blurred: the
            // esm filter's storage
  evsm2_moments,  // the depth plus (e^(cz), e^(2cz)) of min(z, 1), RG32F (RG16F with d16): the evsm2 filter's
                  // storage
  evsm4_moments,  // the depth plus (e^(cz), e^(2cz), -e^(-cz), e^(-2cz)), RGBA32F (RGBA16F with d16): evsm4's
                  // storage
  msm_moments,    // the depth plus (z, z^2, z^3, z^4) of min(z, 1), RGBA32F (RGBA16F with d16): the msm
                  // filter's storage
};
enum class DepthFormat { d16, d24, d32f };
// How the point light's depth is stored and looked up (backends/common/layouts.h holds each
// layout's row).
enum class Layout {
  cube,  // a cube map sampled by direction: the hardware picks the face and filters across seams (seamless)
  face_array,  // the six faces as layers of a 2D array (Filament's six 2D maps): the shader picks the layer
               // and (s, t) by the cube-map rule, and filtering clamps at each face's edge
  dual_paraboloid,  // two hemispheres, each a paraboloid warped in the shadow pass's vertex stage (Godot's
                    // "faster, lower quality"; backends/common/paraboloid.h), layers sized to a cube's memory
  tetrahedral,  // four perspective faces along a tetrahedron's vertices (bgfx's point light; backends/common/
                // tetrahedron.h), each a layer of a 2D array sized to a cube's memory
  cube_array,   // every point light's cube in one cube-map array (GL 4.0 core, Vulkan imageCubeArray): the
                // sampler picks the face as for a cube, the light is the array index
  atlas,        // every point light's faces as bordered tiles of one 2D texture (Godot's, HDRP's and
          // Filament's shadow atlas; backends/common/atlas.h): the shader picks the face by the cube-map
          // rule and clamps to its tile
};

// How a case's point lights group the shadow pass's draws: each light in its own pass (six_pass: six a light,
// 6K in all; a single-pass technique: one a light, K), or every light in one pass (vs_layer: one instance per
// light and face, gl_Layer = 6 light + face, into one layered framebuffer of every light's layers).
enum class LightGrouping {
  per_light,
  all_lights,
};
// geometry_shader with every light in one pass: shaders/shadow_depth.geom's 32 invocations (the least every
// device allows) of two lights each.
inline constexpr int kAllLightsGeometryMaxLights = 64;

// How layout atlas sizes each light's tiles (backends/common/atlas.h): every light at --cube, or by the share
// of the view its range covers (from the camera and the lights at frame 0: a light's range sphere subtends an
// angle proportional to range / distance, so a light twice as far for its range gets half the texels a side).
// by_coverage: each light's faces by the screen area its range covers at frame 0, within a texel budget
// (CaseConfig::shadow_budget_texels).
enum class AtlasTiles {
  uniform,
  by_distance,
  by_coverage,
};

std::string_view to_string(Technique v);
std::string_view to_string(Filter v);
std::string_view to_string(Storage v);
std::string_view to_string(DepthFormat v);
std::string_view to_string(Layout v);
std::string_view to_string(LightGrouping v);
std::string_view to_string(AtlasTiles v);

// Parse a spelling; throws std::invalid_argument("unknown technique 'x' (valid: six_pass, ...)").
template <typename E>
E parse_enum(std::string_view text);
template <typename E>
std::vector<E> all_values();
template <typename E>
std::string valid_values();  // "six_pass, geometry_shader, ..."

struct Support {
  bool ok = true;
  std::string reason;  // why not, in one line: "GL_ARB_shader_viewport_layer_array not exposed"
};

// Work-avoiding switches (do only the work a scene requires). Each is measured on and off in one run;
// images must agree with the unoptimised six_pass case (bit-exact for culling and caching, where the maths is
// the same; fit_range changes the stored depth's scale and is checked against six_pass with the same switch).
struct Optimizations {
  bool face_culling =
      false;               // six_pass: objects culled per face on the CPU, empty faces only cleared;
                           // GS techniques: triangles emitted only to faces they touch; vs_layer: per-object
                           // face masks (instances only for faces the bounds touch). multiview: unsupported.
  bool fit_range = false;  // light far plane fitted to the scene bounds around the light (never beyond the
                           // scene's far): linear depth's step is far / 2^bits, so a tighter far is precision
  bool static_cache =
      false;  // the cube is not re-rendered while its light and the casters within reach stand still
  // A light whose range misses the camera's frustum gets no pass, a face no lookup of a visible point can
  // read is cleared only (backends/common/view_culling.h).
  bool view_culling = false;
  // The lighting pass shades each pixel with its cluster's lights, from lists built each frame
  // (backends/common/light_clusters.h).
  bool light_clusters = false;
  bool any() const { return face_culling || fit_range || static_cache || view_culling || light_clusters; }
  bool operator==(const Optimizations&) const = default;
};
// Remedies for numerical extremes (the stability suite, scripts/experiments/run_extremes.sh), measured on and
// off like the optimisations; each appends its word to the case id.
//   rebase_origin: the scene is loaded relative to its light in double precision (scene::LoadOptions): the
//                  remedy for far-from-origin cancellation.
//   bias:          the cube lookups' bias: the tutorials' constants (0.05; 0.15 for the disk), zero, or the
//   directional notes'
//                  slope-scaled max(0.05 (1 - n.l), 0.005) (world units here).
//   normal_offset: the lookup point moves 1.5 cube texels (at its distance) along the surface normal.
//   two_sided:     casters are drawn two-sided in the shadow pass (no back-face culling), so a light inside a
//                  closed caster is blocked by it.
enum class BiasMode {
  tutorial,
  zero,
  slope
};  // tutorial: the tutorials' constant bias (0.05 hard, 0.15 disk PCF)
struct Remedies {
  bool rebase_origin = false;
  BiasMode bias = BiasMode::tutorial;
  bool normal_offset = false;
  bool two_sided = false;
  bool any() const { return rebase_origin || bias != BiasMode::tutorial || normal_offset || two_sided; }
  bool operator==(const Remedies&) const = default;
};
// "none" or a '+' join of rebase, bias0, slope_bias, normal_offset, two_sided; throws std::invalid_argument.
Remedies parse_remedies(std::string_view text);
std::string to_string(const Remedies& r);  // the same spellings; "none" when all are off

// The moments filters' knobs, swept by the extremes suite (docs/extremes.md, "Moments filters' hazards"); the
// defaults are what every other run uses. Each knob that differs from its default appends its word to the id.
//   bleed_reduction a (lbr<a>):   vsm, evsm2, evsm4, msm: the lit fraction p becomes clamp((p - a) / (1 - a),
//   0, 1),
//                                 which removes light bleeding below a at the cost of darkening penumbrae;
//   exponent_fraction f (exp<f>): esm, evsm2, evsm4: the exponent c as a fraction of the format's overflow
//   limit
//                                 (ln of its largest finite value; half of it for evsm, which stores
//                                 e^(2cz)); above 1 the moments of z near 1 are infinite;
//   floor_scale s (floor<s>):     vsm's variance floor and msm's moment bias as a multiple of their defaults
//                                 (moments_parameter); 0 turns them off;
//   world_units (world):          vsm stores (d, d^2) of the distance d in world units rather than d / far
//   (the
//                                 floor is relative to m2, so only the format's range differs: d^2 overflows
//                                 a 16-bit float beyond 256 units).
struct MomentsTuning {
  float bleed_reduction = 0.0f;
  float exponent_fraction = 0.9f;
  float floor_scale = 1.0f;
  bool world_units = false;
  bool any() const { return *this != MomentsTuning{}; }
  bool operator==(const MomentsTuning&) const = default;
};
// "none" or a '+' join of lbr<a> (0 <= a < 1), exp<f> (0 < f <= 2), floor<s> (0 <= s <= 1e6), world; throws
// std::invalid_argument naming the word.
MomentsTuning parse_moments_tuning(std::string_view text);
std::string to_string(const MomentsTuning& t);  // the same spellings, numbers as %g; "none" at the defaults

// "none", "cull", "fit", "cache", "view", "clusters" or a '+' join such as "cull+fit"; throws
// std::invalid_argument naming the word.
Optimizations parse_optimizations(std::string_view text);
std::string to_string(const Optimizations& o);  // the same spellings; "none" when all are off

struct CaseConfig;
// Layout cube with several point lights: one samplerCube per light (layouts.h, kLightCubes).
bool light_cubes(const CaseConfig& config);

struct CaseConfig {
  std::string backend = "gl";
  std::string scene = "room";
  int cube_size = 512;
  int width = 800;
  int height = 600;
  Technique technique = Technique::six_pass;
  Filter filter = Filter::hard;
  Storage storage = Storage::linear_depth;
  DepthFormat depth_format = DepthFormat::d32f;
  Layout layout = Layout::cube;  // in the id as /face_array after the depth format; nothing for the cube
  // Every triangle of the scene subdivided into tessellation^2 (--tessellate; scenes/tessellate.h): the same
  // surfaces in more, smaller triangles, for layouts whose error depends on it. In the id as /t<n> unless 1.
  int tessellation = 1;
  // The first light_count point lights of the scene (--light-count; scenes/README.md), each with its own
  // shadow map. In the id as /l<K> when above 1, so that a one-light case keeps its id.
  int light_count = 1;
  // --light-grouping; in the id as /all_lights for every light in one pass, nothing per light.
  LightGrouping light_grouping = LightGrouping::per_light;
  // --atlas-tiles (layout atlas only); in the id as /tiles_by_distance, nothing for uniform.
  AtlasTiles atlas_tiles = AtlasTiles::uniform;
  // --shadow-budget (atlas by_coverage only): the atlas's texels at most; 0: the uniform atlas's (the same
  // memory, given by coverage). In the id as /budget<texels> when set.
  uint64_t shadow_budget_texels = 0;
  // --atlas-replan (atlas by_distance and by_coverage only): the tiles planned again every this many frames,
  // from that frame's camera and lights, within the atlas allocated at configure (backends/common/atlas.h
  // plan_at); 0: planned once, from frame 0. In the id as /replan<frames> when set.
  int atlas_replan_frames = 0;
  // --atlas-hysteresis (with re-plans only): at a re-plan a light keeps its face size while the tiling's rule
  // gives that size for a need (distance or coverage) within a factor 2^octaves of its own, so that a need
  // near a size's edge does not resize it, and render it whole, back and forth (atlas.h face_sizes_within);
  // 0: each re-plan sizes by that frame alone. In the id as /hysteresis<octaves> when set.
  float atlas_hysteresis_octaves = 0.0f;
  // --update-budget: at most this many cube faces rendered a frame, the faces whose content is stale (their
  // light moved since they were rendered) oldest first; the others keep what they hold
  // (backends/common/shadow_frame.h). 0: every stale face every frame. In the id as /update<faces> when set.
  int update_budget_faces = 0;
  Optimizations optimizations;
  Remedies remedies;
  MomentsTuning moments;  // --moments-tuning; in the id as /lbr0.5/exp1.01/floor0/world where not the default
  // Extra fragment work for sensitivity experiments (--inject-fragment-work). With one value it is not in the
  // id, so that an injected run's cases compare against the same ids without it.
  int injected_work = 0;
  // Id segments of the experiment axes that have more than one value (bench/run/matrix.h: "inj18", "rep1",
  // "inj18/rep1"): the same-run A/A and A/B designs of scripts/experiments/sensitivity_same_run.py. Empty in
  // every other run.
  std::string experiment;
  // The PCF kernels' radius as a multiple of the tutorials' (grid offset 0.1, disk radius, 2D maps' one
  // texel); an axis of the stability suite (0 collapses every kernel to one direction). In the id as
  // /pcf<scale> unless 1.
  float pcf_scale = 1.0f;
  // Test only (--raster-perturb): every vertex of the shadow and map passes moved in window space by up to
  // this many of the device's sub-pixel steps, by a fixed linear map of clip space
  // (shaders/raster_perturb.glsl: shared vertices move alike, meshes stay closed, and clipping cannot amplify
  // it). It makes a CPU rasteriser place edges as another conformant one may, to prove the texel truths'
  // bounds (bench/truth/texel_bounds.h) hold there. 0 in every real run: the shaders then fold it away. Not
  // in the id.
  float raster_perturb_steps = 0.0f;
  // Test only (--lookup-perturb): every cube lookup of the lighting pass moved by this many texels along both
  // of its face's axes (shaders/shadow_filters.glsl, shadow_coord), as a sampler that quantises texel
  // coordinates more coarsely may read; proves the lookup check's bound (bench/truth/lookup_check.h). 0 in
  // every real run. Not in the id.
  float lookup_perturb_texels = 0.0f;
  // Test only (--emulate-nv-swizzle): nv_swizzle without its NV extensions, on any device with a geometry
  // shader. An ordinary GS emits each triangle once per face with the face's swizzle applied in the shader
  // (the table of backends/common/viewport_swizzle.h, passed as defines) and gl_Layer = face, into one
  // viewport. Everything else is nv_swizzle's own: the vertex stage, the viewport mask and its culling, the
  // reversed depth test and clear, the checks; so CPU drivers prove all of it but the passthrough GS and the
  // swizzle state. Off in every real run; ids end in /emulated.
  bool emulate_nv_swizzle = false;
  // Test only (--emulate-mesh-shader): mesh_shader without mesh shading, on any device that writes gl_Layer
  // from the vertex stage. The task stage runs as a compute shader (shaders/shadow_mesh_task.comp) whose
  // workgroups write their entries and an indirect draw each; the mesh stage runs as a vertex shader
  // (shadow_mesh_emulation.vert), an instance per mesh workgroup. Both run mesh_common.glsl's functions and
  // the task body the native stage runs (mesh_task.glsl), so CPU drivers prove the meshlets, the routing per
  // light and face, the culling and the layers; not the extension's own stages. Off in every real run; ids
  // end in /emulated.
  bool emulate_mesh_shader = false;

  // gl/room/c1024/f800x600/six_pass/pcf_disk20/linear_depth/d32f: unique per case, stable across runs,
  // usable in --benchmark_filter regexes and as a folder path for the case's images. Optimisations that are
  // on append a segment each (/cull, /fit, /cache), as do remedies (/rebase, /bias0, ...), so ids without
  // them are unchanged.
  std::string id() const;
  // The id's segments for the atlas's tiles: /tiles_<tiling>, /budget, /replan, /hysteresis where set (the
  // summary's pass groups key by them too).
  std::string atlas_tiling_id() const;
  bool operator==(const CaseConfig&) const = default;
};

}  // namespace omnishadow
