// The shadow lookups and PCF kernels, one place for both APIs. Biases and kernels are the seeds':
// hard 0.05 (seed 000), 4x4x4 grid of +-0.1 with bias 0.05 and the 20-direction disk with bias 0.15 (seed 001).
// Requires common.glsl.

#if defined(FILTER_HW_COMPARE2X2)
layout(binding = 2) uniform samplerCubeShadow shadow_map;  // LINEAR + compare: 2x2 bilinear PCF in hardware
#else
layout(binding = 2) uniform samplerCube shadow_map;        // NEAREST, no compare
#endif

// What the shadow pass stored, as a distance from the light in world units.
float stored_to_distance(float stored) {
#if defined(STORAGE_R32F_DISTANCE)
  return stored;
#else
  return stored * light_far();
#endif
}

#if !defined(FILTER_HW_COMPARE2X2)
// 1 when `current` lies behind what the light saw in direction `dir` (shadowed), else 0.
float occluded(vec3 dir, float current, float bias) {
  return current - bias > stored_to_distance(texture(shadow_map, dir).r) ? 1.0 : 0.0;
}
#endif

const vec3 kDiskDirections[20] = vec3[](
    vec3(1, 1, 1), vec3(1, -1, 1), vec3(-1, -1, 1), vec3(-1, 1, 1),
    vec3(1, 1, -1), vec3(1, -1, -1), vec3(-1, -1, -1), vec3(-1, 1, -1),
    vec3(1, 1, 0), vec3(1, -1, 0), vec3(-1, -1, 0), vec3(-1, 1, 0),
    vec3(1, 0, 1), vec3(-1, 0, 1), vec3(1, 0, -1), vec3(-1, 0, -1),
    vec3(0, 1, 1), vec3(0, -1, 1), vec3(0, -1, -1), vec3(0, 1, -1));

float shadow_factor(vec3 world_pos) {
  vec3 frag_to_light = world_pos - frame.light_position.xyz;  // the seed's name: it points away from the light
  float current = length(frag_to_light);
#if defined(FILTER_HARD)
  return occluded(frag_to_light, current, 0.05);
#elif defined(FILTER_PCF_GRID64)
  // The seed steps a float from -offset by offset/2 while < offset; accumulated rounding can add a fifth step
  // (125 samples divided by 64). Integer steps give exactly the intended 4 offsets: -0.1, -0.05, 0, 0.05.
  const float offset = 0.1;
  const float step_size = offset / 2.0;
  float shadow = 0.0;
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y)
      for (int z = 0; z < 4; ++z)
        shadow += occluded(frag_to_light + vec3(-offset) + step_size * vec3(x, y, z), current, 0.05);
  return shadow / 64.0;
#elif defined(FILTER_PCF_DISK20)
  float view_distance = length(frame.camera_position.xyz - world_pos);
  float disk_radius = (1.0 + view_distance / light_far()) / 25.0;  // sharper near the viewer (seed 001)
  float shadow = 0.0;
  for (int i = 0; i < 20; ++i) shadow += occluded(frag_to_light + kDiskDirections[i] * disk_radius, current, 0.15);
  return shadow / 20.0;
#elif defined(FILTER_HW_COMPARE2X2)
  // Reference value in the stored units (distance / far); the sampler returns the lit fraction.
  return 1.0 - texture(shadow_map, vec4(frag_to_light, (current - 0.05) / light_far()));
#else
#error "no FILTER_* defined"
#endif
}
