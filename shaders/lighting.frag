#version 450
// Lighting pass: Blinn-Phong as in seed 001/002, with the shadow term from the selected filter.
#include "common.glsl"
#include "shadow_filters.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in vec3 albedo;

layout(location = 0) out vec4 out_color;
layout(location = 1) out float out_shadow_factor;  // 1 = fully shadowed (the seed's `shadow`)
layout(location = 2) out vec4 out_position;        // world position, w = 1 marks covered pixels

void main() {
  vec3 normal = normalize(world_normal);
  vec3 light_color = frame.light_color.rgb;
  vec3 ambient = 0.3 * albedo;
  vec3 light_dir = normalize(frame.light_position.xyz - world_position);
  float diff = max(dot(light_dir, normal), 0.0);
  vec3 diffuse = diff * light_color;
  vec3 view_dir = normalize(frame.camera_position.xyz - world_position);
  vec3 halfway = normalize(light_dir + view_dir);
  vec3 specular = pow(max(dot(normal, halfway), 0.0), 64.0) * light_color;

  float shadow = shadow_factor(world_position);
  // Injected work, off by default (--inject-fragment-work N): N dependent multiply-adds per fragment, real work
  // of a known size for proving that the regression statistics see a slowdown. It cannot change the image:
  // 1e-9 * acc is below half an ulp of 1.0.
  float acc = 0.0;
  for (int i = 0; i < int(frame.knobs.x); ++i) acc = fract(acc * 1.61803 + 0.31831);
  out_color = vec4((ambient + (1.0 - shadow) * (diffuse + specular)) * albedo, 1.0 - 1e-9 * acc);
  out_shadow_factor = shadow;
  out_position = vec4(world_position, 1.0);
}
