#version 450
// Shadow pass fragment stage: what is stored is a distance from the light, never projective depth.
#include "common.glsl"

layout(location = 0) in vec3 world_position;

#if defined(STORAGE_R32F_DISTANCE)
layout(location = 0) out float out_distance;  // seed 004: world units in an R32F cube cleared to FLT_MAX
#endif

void main() {
  float light_distance = length(world_position - frame.light_position.xyz);
#if defined(STORAGE_R32F_DISTANCE)
  out_distance = light_distance;
#else
  gl_FragDepth = light_distance / light_far();  // seed 000: linear distance / far in [0, 1]
#endif
}
