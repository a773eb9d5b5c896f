#version 450
// Shadow pass vertex stage. Vertices arrive in world space (scenes are baked at load).
#if defined(TECHNIQUE_VS_LAYER)
#extension GL_ARB_shader_viewport_layer_array : require
#elif defined(TECHNIQUE_MULTIVIEW)
#extension GL_EXT_multiview : require
#endif
#include "common.glsl"

layout(location = 0) in vec3 in_position;

#if defined(TECHNIQUE_SIX_PASS) || defined(TECHNIQUE_VS_LAYER) || defined(TECHNIQUE_MULTIVIEW)
layout(location = 0) out vec3 world_position;
#endif

void main() {
#if defined(TECHNIQUE_SIX_PASS)
  world_position = in_position;
  gl_Position = frame.face_view_proj[pass.face] * vec4(in_position, 1.0);
#elif defined(TECHNIQUE_VS_LAYER)
  // Six instances, one per face, in face order.
#ifdef VULKAN
  int face = gl_InstanceIndex;
#else
  int face = gl_InstanceID;
#endif
  gl_Layer = face;
  world_position = in_position;
  gl_Position = frame.face_view_proj[face] * vec4(in_position, 1.0);
#elif defined(TECHNIQUE_MULTIVIEW)
  // One draw, six views (view mask 0b111111): the view index picks the face.
  int face = int(gl_ViewIndex);
  world_position = in_position;
  gl_Position = frame.face_view_proj[face] * vec4(in_position, 1.0);
#else
  // Geometry-shader techniques transform per face in the GS.
  gl_Position = vec4(in_position, 1.0);
#endif
}
