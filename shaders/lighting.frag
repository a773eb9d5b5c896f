#version 450
// Lighting pass: Blinn-Phong as in the point-shadow tutorial (docs/glossary.md), with the shadow term from the
// selected filter.
//
// Two variants of one source (backends/common/shader_variants.h): the timed variant is what a renderer ships for
// the case, one colour output and only the lights the scene has; CHECK_OUTPUTS adds the shadow factor and world
// position the checks read, rendered in the untimed check frame. Every line that computes the colour is shared,
// so the two lit images agree bit for bit (the harness checks it per case: check "timed_lit").
#define POINT_LIGHT_LIST  // every point light from a list (common.glsl), not the shadow pass's one light
#include "common.glsl"
#include "shadow_filters.glsl"

// What the case has, fixed when the pipeline is built so that nothing the case lacks is in the shader: GL gets
// them as defines, Vulkan as specialisation constants (ids 0-2, gpu::LightingConstants).
#ifdef VULKAN
layout(constant_id = 0) const int kMapLights = 0;     // spot and directional lights, 0-4, one 2D map each
layout(constant_id = 1) const int kPointLights = 1;   // point lights shaded (the case's light count; 0: none)
layout(constant_id = 2) const int kInjectedWork = 0;  // --inject-fragment-work (0 = none)
layout(constant_id = 4) const bool kLightClusters = false;  // --optimize clusters: the pixel's cluster's lights
#else
const int kMapLights = MAP_LIGHTS;
const int kPointLights = POINT_LIGHTS;
const int kInjectedWork = INJECTED_WORK;
const bool kLightClusters = LIGHT_CLUSTERS != 0;
#endif

// Clustered light lists (backends/common/light_clusters.h, its layout): a header, each cluster's first index
// word and light count, then the lights' indices in the scene's order.
const uint kClusterHeaderWords = 16u;
layout(std430, binding = 10) readonly buffer LightClusters { uint cluster_words[]; };

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in vec3 albedo;

layout(location = 0) out vec4 out_color;
#ifdef CHECK_OUTPUTS
layout(location = 1) out float out_shadow_factor;  // 1 = fully shadowed (the tutorial's `shadow`)
layout(location = 2) out vec4 out_position;        // world position, w = 1 marks covered pixels
#endif

// This pixel's cluster: its screen tile (row 0 first in memory in both APIs) and the slice of its view depth,
// gpu::cluster_of's arithmetic.
uint pixel_cluster() {
  uvec2 tiles = uvec2(cluster_words[0], cluster_words[1]);
  uvec2 tile = min(uvec2(gl_FragCoord.xy) / cluster_words[3], tiles - 1u);
  vec3 forward = uintBitsToFloat(uvec3(cluster_words[4], cluster_words[5], cluster_words[6]));
  float near_plane = uintBitsToFloat(cluster_words[7]);
  float depth = dot(world_position - frame.camera_position.xyz, forward);
  float slice = floor(log(max(depth, near_plane) / near_plane) * uintBitsToFloat(cluster_words[8]));
  uint s = uint(clamp(int(slice), 0, int(cluster_words[2]) - 1));
  return (s * tiles.y + tile.y) * tiles.x + tile.x;
}

// Blinn-Phong diffuse + specular of one light (the tutorial's shininess 64).
vec3 direct_light(vec3 normal, vec3 light_dir, vec3 view_dir, vec3 light_color) {
  float diff = max(dot(light_dir, normal), 0.0);
  vec3 halfway = normalize(light_dir + view_dir);
  return diff * light_color + pow(max(dot(normal, halfway), 0.0), 64.0) * light_color;
}

void main() {
  vec3 normal = normalize(world_normal);
  vec3 ambient = 0.3 * albedo;
  vec3 view_dir = normalize(frame.camera_position.xyz - world_position);
  // Each point light with its own shadow map, summed. The reported shadow factor is light
  // frame.lights_info.z's (the check variant renders once per light the checks read).
  vec3 point_term = vec3(0.0);
  float shadow = 0.0;
  int reported_light = int(frame.lights_info.z);
  // Every light, or with clusters the pixel's cluster's lights: the same lights that reach the pixel in the same
  // order, so the same sum (a light out of range adds an exact 0 in the loop over all). The cluster's loop is
  // not uniform across a quad, so implicit derivatives are undefined there; they only choose the level of
  // detail, and every shadow texture has one level and equal minification and magnification filters.
  uint first = 0u, count = uint(kPointLights);
  if (kLightClusters) {
    uint entry = kClusterHeaderWords + 2u * pixel_cluster();
    first = cluster_words[entry];
    count = cluster_words[entry + 1u];
  }
  for (uint i = 0u; i < count; ++i) {
    int k = kLightClusters ? int(cluster_words[first + i]) : int(i);
    g_light = k;  // the shadow map's layers and the record of light k
    vec3 light_color = point_lights[k].colour_near.rgb;
    vec3 to_light = light_position() - world_position;
    // The light's range is its far plane: beyond it the light reaches nothing, whatever the filter would make of
    // the cube there (glTF's range; what lets a renderer skip a light). As outside a spot's cone, the shadow
    // factor there is 0 and the light adds nothing. Every bundled one-light scene lies within its light's far.
    // Without clusters the lookup stays in uniform control flow, the range only masks its result.
    bool in_range = length(to_light) < light_far();
    vec3 light_dir = normalize(to_light);
    float diff = max(dot(light_dir, normal), 0.0);
    vec3 diffuse = diff * light_color;
    vec3 halfway = normalize(light_dir + view_dir);
    vec3 specular = pow(max(dot(normal, halfway), 0.0), 64.0) * light_color;
    float looked_up = shadow_factor(world_position, normal);  // not in the ?: (it evaluates one side only)
    float light_shadow = in_range ? looked_up : 0.0;
    if (k == reported_light) shadow = light_shadow;
    point_term += in_range ? (1.0 - light_shadow) * (diffuse + specular) : vec3(0.0);
  }
  // Spot and directional lights, each with its 2D map. The reported shadow factor is the first light's.
  vec3 mapped = vec3(0.0);
  for (int i = 0; i < kMapLights; ++i) {
    bool spot = frame.map_light[i].w < 1.5;
    vec3 light_dir = spot ? normalize(frame.map_light[i].xyz - world_position) : frame.map_light[i].xyz;
    bool inside;
    float s = map_shadow_factor(i, world_position, normal, light_dir, inside);
    if (i == 0 && kPointLights == 0) shadow = s;
    if (inside) mapped += (1.0 - s) * direct_light(normal, light_dir, view_dir, frame.map_color[i].rgb);
  }
  // Injected work (--inject-fragment-work N): N dependent multiply-adds per fragment, real work of a known size
  // for proving that the regression statistics see a slowdown. It cannot change the image: 1e-9 * acc is below
  // half an ulp of 1.0. The chain starts from the fragment's position: from a constant, a compiler that knows N
  // (a specialised shader) unrolls and folds it away, and the work is not done (seen: 20 iterations cost nothing,
  // 80 cost 40%). With N = 0 the seed folds to 0 and the frame is what it was.
  float acc = kInjectedWork > 0 ? fract(gl_FragCoord.x * 0.618034) : 0.0;
  for (int i = 0; i < kInjectedWork; ++i) acc = fract(acc * 1.61803 + 0.31831);
  // With no map lights `mapped` is 0 and adding it changes no bit: point-light scenes render as before (and one
  // point light's term is added to 0 exactly).
  out_color = vec4((ambient + point_term + mapped) * albedo, 1.0 - 1e-9 * acc);
#ifdef CHECK_OUTPUTS
  out_shadow_factor = shadow;
  out_position = vec4(world_position, 1.0);
#endif
}
