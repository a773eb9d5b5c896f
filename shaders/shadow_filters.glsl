// The shadow lookups and PCF kernels, one place for both APIs. Biases and kernels are the tutorials' (docs/glossary.md):
// hard 0.05 (the point-shadow tutorial), 4x4x4 grid of +-0.1 with bias 0.05 and the 20-direction disk with bias 0.15 (the point-shadow tutorial).
// Requires common.glsl.

// Test only (--lookup-perturb, CaseConfig::lookup_perturb_texels): every cube lookup moved by this many texels along
// both axes of its face, as a sampler that quantises texel coordinates more coarsely may read. 0 in every real run,
// and perturb_lookup() folds to its argument. Vulkan: specialisation constant 3 (gpu::LightingConstants).
#ifdef VULKAN
layout(constant_id = 3) const float kLookupPerturbTexels = 0.0;
#else
const float kLookupPerturbTexels = LOOKUP_PERTURB_TEXELS;
#endif

// The direction moved by kLookupPerturbTexels texels of a face of `size` along both minor axes (a texel spans
// 2 |major| / size of a minor component), clamped to its face: a sampler picks the face first, then the texel.
vec3 perturb_lookup(vec3 dir, float size) {
  if (kLookupPerturbTexels == 0.0) return dir;
  vec3 a = abs(dir);
  float major = max(a.x, max(a.y, a.z));
  // Minor components stay strictly inside the face (a tie would let the face change, which a sampler never does).
  float inside = major * (1.0 - 1e-6);
  vec3 moved = clamp(dir + vec3(2.0 * major * kLookupPerturbTexels / size), -vec3(inside), vec3(inside));
  if (a.x == major) moved.x = dir.x;
  else if (a.y == major) moved.y = dir.y;
  else moved.z = dir.z;
  return moved;
}

#if defined(LAYOUT_FACE_ARRAY) || defined(LAYOUT_DUAL_PARABOLOID) || defined(LAYOUT_TETRAHEDRAL) || defined(LAYOUT_ATLAS)
// Every layout but the cube stores layers of a 2D array and picks the layer and (s, t) in the shader (shadow_coord,
// per layout below); filtering clamps at each layer's edge. With several point lights, light k's layers follow
// light k - 1's: layer = k x the layout's layers + the light's own layer (backends/common/layouts.h).
#if defined(FILTER_HW_COMPARE2X2)
layout(binding = 2) uniform sampler2DArrayShadow shadow_map;  // LINEAR + compare, clamped to the layer
#else
layout(binding = 2) uniform sampler2DArray shadow_map;        // NEAREST, no compare; LINEAR for moments
#endif
#endif

#if defined(LAYOUT_FACE_ARRAY) || defined(LAYOUT_ATLAS)
// (s, t, face) of the face `dir` selects by the cube-map rule (GL 4.5 table 8.19, as cube::direction_to_face: ties
// to x, then y): what a samplerCube computes before it reads a texel.
vec3 cube_face_coord(vec3 dir) {
  vec3 a = abs(dir);
  float face, sc, tc, ma;
  if (a.x >= a.y && a.x >= a.z) {
    face = dir.x >= 0.0 ? 0.0 : 1.0;
    ma = a.x;
    sc = dir.x >= 0.0 ? -dir.z : dir.z;
    tc = -dir.y;
  } else if (a.y >= a.z) {
    face = dir.y >= 0.0 ? 2.0 : 3.0;
    ma = a.y;
    sc = dir.x;
    tc = dir.y >= 0.0 ? dir.z : -dir.z;
  } else {
    face = dir.z >= 0.0 ? 4.0 : 5.0;
    ma = a.z;
    sc = dir.z >= 0.0 ? dir.x : -dir.x;
    tc = -dir.y;
  }
  return vec3(0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0), face);
}
#endif

// A face's edge in texels (defined below, once the layout's sampler is declared).
float shadow_face_size();

#if defined(LAYOUT_FACE_ARRAY)
// Layout face_array (backends/common/layouts.h): the six faces are layers of a 2D array, as a renderer that treats a
// point light as six spot maps stores them. The shader picks the layer and (s, t) by the cube-map rule, and
// filtering clamps at each face's edge.
vec3 shadow_coord(vec3 dir) {
  vec3 c = cube_face_coord(perturb_lookup(dir, shadow_face_size()));
  return vec3(c.xy, c.z + 6.0 * float(g_light));
}
#elif defined(LAYOUT_ATLAS)
// Layout atlas (backends/common/atlas.h holds the same arithmetic: change both together): light k's faces are tiles
// of one layer, face f at column f % 3 and row f / 3 of the light's block, each N texels inside a border. (s, t) is
// clamped to the face's first and last texel centres, as face_array's sampler clamps at a layer's edge: a NEAREST
// tap never leaves the face, a LINEAR one reads the border with weight 0.
vec3 shadow_coord(vec3 dir) {
  vec3 c = cube_face_coord(perturb_lookup(dir, shadow_face_size()));
  const vec4 tile = point_lights[g_light].atlas_tile;  // xy block origin, z face edge N, w border (texels)
  const float span = tile.z + 2.0 * tile.w;
  const vec2 in_face = clamp(c.xy * tile.z, vec2(0.5), vec2(tile.z - 0.5));
  const int face = int(c.z);  // integer column and row: a float division by 3 may round below 1
  const vec2 texel = tile.xy + vec2(face % 3, face / 3) * span + vec2(tile.w) + in_face;
  return vec3(texel / vec2(textureSize(shadow_map, 0).xy), 0.0);
}
#elif defined(LAYOUT_DUAL_PARABOLOID)
// Layout dual_paraboloid (shaders/paraboloid.glsl): two layers of a 2D array, each a hemisphere's paraboloid.
#include "paraboloid.glsl"
vec3 shadow_coord(vec3 dir) { return paraboloid_coord(dir) + vec3(0.0, 0.0, 2.0 * float(g_light)); }
#elif defined(LAYOUT_TETRAHEDRAL)
// Layout tetrahedral (backends/common/tetrahedron.h holds the same rule in C++: change both together): four
// perspective faces along a regular tetrahedron's vertices, each a layer of a 2D array. A direction reads the face
// whose axis is nearest (ties to the lower face), projected onto that face's plane one unit along its axis, whose
// frustum is the box x in [-sqrt 6, sqrt 6], y in [-sqrt 2, 2 sqrt 2] (the cell's bounding box).
// The bases in closed form, as integer vectors times 1/sqrt 3 (axes), 1/sqrt 6 (ups) and 1/sqrt 2 (rights):
// tetrahedron.h derives the same from the rule (up: the corner opposite the next face, -axis[(f + 1) % 4], made
// orthogonal to the axis; right = axis x up, a GL camera's, as lookAt builds it), and tetrahedron_test reads these
// lines to hold them equal. Every lookup of a filter's kernel runs this, so it selects with constant indices and
// no runtime basis: the loop over a dynamically indexed array with a normalize and a cross per lookup made
// pcf_disk20's lighting pass 5.6x the cube's on llvmpipe (3.0-3.2x on an H100).
const vec3 kTetraAxes[4] = vec3[](vec3(1, 1, 1), vec3(1, -1, -1), vec3(-1, 1, -1), vec3(-1, -1, 1));
const vec3 kTetraUps[4] = vec3[](vec3(-2, 1, 1), vec3(1, -1, 2), vec3(2, 1, -1), vec3(-1, -1, -2));
const vec3 kTetraRights[4] = vec3[](vec3(0, -1, 1), vec3(-1, -1, 0), vec3(0, -1, -1), vec3(1, -1, 0));
vec3 shadow_coord(vec3 dir) {
  // The face whose axis is nearest: the largest dot product, ties to the lower face (strict >).
  const vec4 d = vec4(dot(dir, kTetraAxes[0]), dot(dir, kTetraAxes[1]), dot(dir, kTetraAxes[2]),
                      dot(dir, kTetraAxes[3])) * 0.57735026919;  // 1 / sqrt 3
  float best = d.x, face = 0.0;
  vec3 up = kTetraUps[0], right = kTetraRights[0];
  if (d.y > best) { best = d.y; face = 1.0; up = kTetraUps[1]; right = kTetraRights[1]; }
  if (d.z > best) { best = d.z; face = 2.0; up = kTetraUps[2]; right = kTetraRights[2]; }
  if (d.w > best) { best = d.w; face = 3.0; up = kTetraUps[3]; right = kTetraRights[3]; }
  const float kSqrt2 = 1.41421356, kSqrt6 = 2.44948974;
  vec2 xy = vec2(dot(dir, right) / kSqrt2, dot(dir, up) / kSqrt6) / best;
  return vec3((xy.x + kSqrt6) / (2.0 * kSqrt6), (xy.y + kSqrt2) / (3.0 * kSqrt2), face + 4.0 * float(g_light));
}
#elif defined(LAYOUT_CUBE_ARRAY)
// Layout cube_array: every light's cube in one cube-map array (GL 4.0 core, Vulkan imageCubeArray), light k the
// k-th cube; the sampler picks the face and filters across its seams as for a cube.
#if defined(FILTER_HW_COMPARE2X2)
layout(binding = 2) uniform samplerCubeArrayShadow shadow_map;  // LINEAR + compare
#else
layout(binding = 2) uniform samplerCubeArray shadow_map;        // NEAREST, no compare; LINEAR for moments
#endif
vec4 shadow_coord(vec3 dir) { return vec4(perturb_lookup(dir, shadow_face_size()), float(g_light)); }
#elif defined(LIGHT_CUBES)
// Layout cube with several lights: a cube and a sampler per light (backends/common/layouts.h, kLightCubes), light k
// read through element k. An array of samplers takes only a dynamically uniform index (GLSL 4.50, 4.1.7; SPIR-V
// without descriptor indexing): g_light is, in the loop over every light (clustered lists are refused). Vulkan:
// binding 2's kLightCubes descriptors; GL: units 16 onwards (gpu::kLightCubesGlUnit), clear of map_shadows' 3.
#if defined(VULKAN)
#define LIGHT_CUBES_BINDING 2
#else
#define LIGHT_CUBES_BINDING 16
#endif
#if defined(FILTER_HW_COMPARE2X2)
layout(binding = LIGHT_CUBES_BINDING) uniform samplerCubeShadow shadow_cubes[16];
#else
layout(binding = LIGHT_CUBES_BINDING) uniform samplerCube shadow_cubes[16];
#endif
#define shadow_map shadow_cubes[g_light]
vec3 shadow_coord(vec3 dir) { return perturb_lookup(dir, shadow_face_size()); }
#else
#if defined(FILTER_HW_COMPARE2X2)
layout(binding = 2) uniform samplerCubeShadow shadow_map;  // LINEAR + compare: 2x2 bilinear PCF in hardware
#else
layout(binding = 2) uniform samplerCube shadow_map;        // NEAREST, no compare; LINEAR for a moments cube
#endif
// A cube is sampled by the direction itself.
vec3 shadow_coord(vec3 dir) { return perturb_lookup(dir, shadow_face_size()); }
#endif

// A face's edge in texels: what a texel spans for the perturbed lookup and the normal offset.
float shadow_face_size() {
#if defined(LAYOUT_ATLAS)
  return point_lights[g_light].atlas_tile.z;
#else
  return float(textureSize(shadow_map, 0).x);
#endif
}

#if defined(FILTER_HW_COMPARE2X2)
// The lit fraction of a compare lookup at reference `ref` (stored units): a cube array's compare reference is an
// argument of its own, every other shadow sampler's the coordinate's last component.
float compare_lookup(vec3 dir, float ref) {
#if defined(LAYOUT_CUBE_ARRAY)
  return texture(shadow_map, shadow_coord(dir), ref);
#else
  return texture(shadow_map, vec4(shadow_coord(dir), ref));
#endif
}
#endif
#include "moments.glsl"

// A perspective projection's window depth back to the distance along its axis (near n, far f): the inverse of
// the depth mapping of each API's clip range.
float perspective_linear(float depth, float n, float f) {
#ifdef VULKAN
  return n * f / (f - depth * (f - n));
#else
  float z = depth * 2.0 - 1.0;
  return 2.0 * n * f / (f + n - z * (f - n));
#endif
}

// What the shadow pass stored in direction `dir`, as a distance from the light in world units.
float stored_to_distance(float stored, vec3 dir) {
#if defined(STORAGE_R32F_DISTANCE)
  return stored;
#elif defined(STORAGE_HARDWARE_DEPTH)
  // Projective depth is the distance along the face's axis: back to a distance along `dir`.
  vec3 a = abs(dir);
  float axis = max(a.x, max(a.y, a.z));
  return perspective_linear(stored, light_near(), light_far()) * length(dir) / axis;
#else
  return stored * light_far();
#endif
}

#if !defined(FILTER_HW_COMPARE2X2) && !defined(FILTER_VSM) && !defined(FILTER_ESM) && !defined(FILTER_EVSM2) && \
    !defined(FILTER_EVSM4) && !defined(FILTER_MSM)
// 1 when `current` lies behind what the light saw in direction `dir` (shadowed), else 0.
float occluded(vec3 dir, float current, float bias) {
  return current - bias > stored_to_distance(texture(shadow_map, shadow_coord(dir)).r, dir) ? 1.0 : 0.0;
}
#endif

const vec3 kDiskDirections[20] = vec3[](
    vec3(1, 1, 1), vec3(1, -1, 1), vec3(-1, -1, 1), vec3(-1, 1, 1),
    vec3(1, 1, -1), vec3(1, -1, -1), vec3(-1, -1, -1), vec3(-1, 1, -1),
    vec3(1, 1, 0), vec3(1, -1, 0), vec3(-1, -1, 0), vec3(-1, 1, 0),
    vec3(1, 0, 1), vec3(-1, 0, 1), vec3(1, 0, -1), vec3(-1, 0, -1),
    vec3(0, 1, 1), vec3(0, -1, 1), vec3(0, -1, -1), vec3(0, 1, -1));

// The bias of a lookup: the tutorials' constant for the filter, or (remedies, CaseConfig::remedies) zero or the
// directional notes' slope-scaled max(0.05 (1 - n.l), 0.005), in world units (docs/glossary.md).
float lookup_bias(float tutorial_bias, vec3 normal, vec3 frag_to_light) {
#if defined(BIAS_ZERO)
  return 0.0;
#elif defined(BIAS_SLOPE)
  return max(0.05 * (1.0 - dot(normal, normalize(-frag_to_light))), 0.005);
#else
  return tutorial_bias;
#endif
}

#if defined(FILTER_PCSS)
// Percentage-closer soft shadows (Fernando 2005) for a spherical light of radius R = knobs.z around the point light.
// Offsets are in the units of frag_to_light (length `current`), where an offset s turns the lookup by s / current
// radians, the angle a width s at the receiver subtends from the light.
// 1. Blocker search over the light's disk as seen from the receiver: a blocker at distance d from the light shades
//    the receiver from the part of the disk within R (current - d) / d of the axis, an offset at the receiver of
//    R (current - d) / d; searching an offset of R finds every blocker at least halfway from the light to the
//    receiver (nearer ones are found where the disk's samples reach them), the usual PCSS compromise.
// 2. The penumbra of the average blocker distance by similar triangles, w = R (current - d) / d, is the disk kernel's
//    radius: the shadow ramps over +-w around the hard edge, as a disk light's does.
float pcss_shadow(vec3 frag_to_light, float current, float bias) {
  float radius = frame.knobs.z;
  float blockers = 0.0, blocker_sum = 0.0;
  for (int i = 0; i < 20; ++i) {
    vec3 dir = frag_to_light + kDiskDirections[i] * radius;
    float stored = stored_to_distance(texture(shadow_map, shadow_coord(dir)).r, dir);
    // The stored distance is along `dir`; its length differs from `current` by the offset, within the bias.
    if (current - bias > stored) {
      blockers += 1.0;
      blocker_sum += stored;
    }
  }
  if (blockers == 0.0) return 0.0;  // nothing between the receiver and the light: lit
  float blocker = blocker_sum / blockers;
  float penumbra = radius * (current - blocker) / max(blocker, 1e-4);
  float shadow = 0.0;
  for (int i = 0; i < 20; ++i) shadow += occluded(frag_to_light + kDiskDirections[i] * penumbra, current, bias);
  return shadow / 20.0;
}
#endif

float shadow_factor(vec3 world_pos, vec3 normal) {
#if defined(NORMAL_OFFSET)
  // Normal-offset remedy: look up from a point 1.5 texels (a 90-degree face's texel at this distance) along the
  // normal, so a surface does not test against its own quantised depth.
  float texel_world = 2.0 * length(world_pos - light_position()) / shadow_face_size();
  world_pos += normal * (1.5 * texel_world);
#endif
  vec3 frag_to_light = world_pos - light_position();  // the tutorial's name: it points away from the light
  float current = length(frag_to_light);
#if defined(FILTER_HARD)
  return occluded(frag_to_light, current, lookup_bias(0.05, normal, frag_to_light));
#elif defined(FILTER_PCF_GRID64)
  // The tutorial steps a float from -offset by offset/2 while < offset; accumulated rounding can add a fifth step
  // (125 samples divided by 64). Integer steps give exactly the intended 4 offsets: -0.1, -0.05, 0, 0.05.
  float grid_offset = 0.1 * frame.knobs.y;  // the tutorial's 0.1, times --pcf-scale
  float step_size = grid_offset / 2.0;
  float bias = lookup_bias(0.05, normal, frag_to_light);
  float shadow = 0.0;
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y)
      for (int z = 0; z < 4; ++z)
        shadow += occluded(frag_to_light + vec3(-grid_offset) + step_size * vec3(x, y, z), current, bias);
  return shadow / 64.0;
#elif defined(FILTER_PCF_DISK20)
  float view_distance = length(frame.camera_position.xyz - world_pos);
  // Sharper near the viewer (the point-shadow tutorial), times --pcf-scale.
  float disk_radius = (1.0 + view_distance / light_far()) / 25.0 * frame.knobs.y;
  float shadow = 0.0;
  float bias = lookup_bias(0.15, normal, frag_to_light);
  for (int i = 0; i < 20; ++i) shadow += occluded(frag_to_light + kDiskDirections[i] * disk_radius, current, bias);
  return shadow / 20.0;
#elif defined(FILTER_PCSS)
  return pcss_shadow(frag_to_light, current, lookup_bias(0.15, normal, frag_to_light));
#elif defined(FILTER_VSM)
  return vsm_shadow(frag_to_light, current, lookup_bias(0.05, normal, frag_to_light));
#elif defined(FILTER_ESM)
  return esm_shadow(frag_to_light, current, lookup_bias(0.05, normal, frag_to_light));
#elif defined(FILTER_EVSM2) || defined(FILTER_EVSM4)
  return evsm_shadow(frag_to_light, current, lookup_bias(0.05, normal, frag_to_light));
#elif defined(FILTER_MSM)
  return msm_shadow(frag_to_light, current, lookup_bias(0.05, normal, frag_to_light));
#elif defined(FILTER_HW_COMPARE2X2)
  // Reference value in the stored units (distance / far); the sampler returns the lit fraction.
  return 1.0 - compare_lookup(frag_to_light, (current - lookup_bias(0.05, normal, frag_to_light)) / light_far());
#else
#error "no FILTER_* defined"
#endif
}

// Spot and directional lights: one layer of a 2D depth-map array each, written with plain projective depth.
// Seed 003's fixes: coordinates outside the map are unshadowed (clamp to border), beyond the far plane
// unshadowed, slope-scaled bias max(0.05 (1 - n.l), 0.005), and a 3x3 PCF for every filter but `hard`. A spot
// light compares linear distances along its axis (its perspective depth is not linear), in world units with the
// same bias formula; a directional map's depth is already linear and is compared in map units as in the notes.
layout(binding = 3) uniform sampler2DArray map_shadows;

// Window depth in [0, 1] from NDC z: Vulkan's clip range is already [0, 1], GL's is [-1, 1].
float window_depth(float ndc_z) {
#ifdef VULKAN
  return ndc_z;
#else
  return ndc_z * 0.5 + 0.5;
#endif
}

// The spot map's window depth back to the distance along the light's axis (perspective projection).
float spot_linear(int i, float depth) { return perspective_linear(depth, frame.map_color[i].w, frame.map_range[i].x); }

float map_occluded(int i, vec2 uv, float current, float bias, bool spot) {
  float stored = texture(map_shadows, vec3(uv, float(i))).r;
  if (spot) return spot_linear(i, current) - bias > spot_linear(i, stored) ? 1.0 : 0.0;
  return current - bias > stored ? 1.0 : 0.0;
}

// Returns the shadow (1 = shadowed) of map light i at world_pos; `inside` is false where a spot light's cone
// does not reach (the caller leaves such fragments unlit by it).
float map_shadow_factor(int i, vec3 world_pos, vec3 normal, vec3 light_dir, out bool inside) {
  bool spot = frame.map_light[i].w < 1.5;
  vec4 clip = frame.map_view_proj[i] * vec4(world_pos, 1.0);
  vec3 ndc = clip.xyz / clip.w;
  vec2 uv = ndc.xy * 0.5 + 0.5;
  float current = window_depth(ndc.z);
  bool on_map = clip.w > 0.0 && all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)));
  inside = !spot || on_map;
  if (!on_map || current > 1.0) return 0.0;  // clamp to border / beyond far: unshadowed (the directional notes)
  float bias = max(0.05 * (1.0 - dot(normal, light_dir)), 0.005);
#if defined(FILTER_HARD)
  return map_occluded(i, uv, current, bias, spot);
#else
  vec2 texel = frame.knobs.y / vec2(textureSize(map_shadows, 0).xy);  // one texel, times --pcf-scale
  float shadow = 0.0;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y) shadow += map_occluded(i, uv + vec2(x, y) * texel, current, bias, spot);
  return shadow / 9.0;
#endif
}
