#version 450
#include "common.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_color;

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec3 albedo;

void main() {
  world_position = in_position;
  world_normal = in_normal;
  albedo = in_color;
  gl_Position = frame.camera_view_proj * vec4(in_position, 1.0);
}
