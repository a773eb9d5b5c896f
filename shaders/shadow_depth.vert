#version 450
// Shadow pass vertex stage. Vertices arrive in world space (scenes are baked at load).
#if defined(TECHNIQUE_VS_LAYER)
#extension GL_ARB_shader_viewport_layer_array : require
#elif defined(TECHNIQUE_MULTIVIEW) && defined(VULKAN)
#extension GL_EXT_multiview : require
#elif defined(TECHNIQUE_MULTIVIEW)
#extension GL_OVR_multiview2 : require
layout(num_views = 6) in;  // GL: the framebuffer's six views of the cube's array layers
#endif
#if defined(ALL_LIGHTS)
#define POINT_LIGHT_LIST  // every light's view-projections from the list (common.glsl)
#endif
#include "common.glsl"
#include "raster_perturb.glsl"
#if defined(LAYOUT_DUAL_PARABOLOID)
#include "paraboloid.glsl"
#endif

layout(location = 0) in vec3 in_position;

#if defined(TECHNIQUE_NV_SWIZZLE) && defined(VULKAN)
// Vulkan matches built-in blocks between stages member for member, and the passthrough stage takes gl_Position
// alone (shadow_swizzle.geom): the validation layer refused glslang's implicit four-member block here on NVIDIA.
out gl_PerVertex { vec4 gl_Position; };
#endif

// DEPTH_ONLY (storage hardware_depth): the fragment stage reads nothing, so nothing is passed to it.
#if (defined(TECHNIQUE_SIX_PASS) || defined(TECHNIQUE_VS_LAYER) || defined(TECHNIQUE_MULTIVIEW) || \
     defined(TECHNIQUE_NV_SWIZZLE)) && !defined(DEPTH_ONLY)
#define WRITE_WORLD_POSITION
layout(location = 0) out vec3 world_position;
#if defined(ALL_LIGHTS)
layout(location = 1) flat out int shadow_light;  // the light whose layer the primitive goes to
#endif
#endif

#if defined(LAYOUT_DUAL_PARABOLOID) && defined(TECHNIQUE_GEOMETRY_SHADER)
// Both layers' warped positions, computed here and only routed by the GS: the same vertex-stage arithmetic as
// six_pass's (the warp's sqrt and division round as the stage that runs them does, and a GS's may differ: llvmpipe's
// did by an ulp on 0.6% of texels), so every technique stores the same values.
layout(location = 1) out vec4 layer_clip0;
layout(location = 2) out vec4 layer_clip1;
layout(location = 3) out vec2 layer_forward;
#endif

void main() {
#if defined(TECHNIQUE_SIX_PASS)
#ifdef WRITE_WORLD_POSITION
  world_position = in_position;
#endif
#if defined(LAYOUT_DUAL_PARABOLOID)
  // One pass per layer: pass.face is the layer, and the other hemisphere is clipped away.
  float forward;
  gl_Position = perturb_raster(paraboloid_clip(pass.face, in_position, forward));
  gl_ClipDistance[0] = forward;
#else
  gl_Position = perturb_raster(frame.face_view_proj[pass.face] * vec4(in_position, 1.0));
#endif
#elif defined(TECHNIQUE_VS_LAYER)
#ifdef VULKAN
  int instance = gl_InstanceIndex;
#else
  int instance = gl_InstanceID;
#endif
#if defined(ALL_LIGHTS)
  // Every light in one pass: instance 6 k + f is light k's face f, into layer 6 k + f of every light's layers.
  int light = instance / 6, face = instance - 6 * light;
  gl_Layer = instance;
#ifdef WRITE_WORLD_POSITION
  world_position = in_position;
  shadow_light = light;
#endif
  gl_Position = perturb_raster(point_lights[light].face_view_proj[face] * vec4(in_position, 1.0));
#else
#if defined(FACE_CULLING)
  // One instance per face the object's bounds touch: instance k renders the k-th set bit of the mask.
  uint mask = pass.face_mask;
  for (int k = 0; k < instance; ++k) mask &= mask - 1u;
  int face = findLSB(mask);
#else
  int face = instance;  // six instances, one per face, in face order
#endif
#if defined(LAYOUT_ATLAS)
  gl_ViewportIndex = face;  // layout atlas: face f's tile is viewport f (one layer)
#else
  gl_Layer = face;
#endif
#ifdef WRITE_WORLD_POSITION
  world_position = in_position;
#endif
  gl_Position = perturb_raster(frame.face_view_proj[face] * vec4(in_position, 1.0));
#endif
#elif defined(TECHNIQUE_MULTIVIEW)
  // One draw, six views (Vulkan: view mask 0b111111; GL: num_views = 6): the view index picks the face.
#ifdef VULKAN
  int face = int(gl_ViewIndex);
#else
  int face = int(gl_ViewID_OVR);
#endif
#ifdef WRITE_WORLD_POSITION
  world_position = in_position;
#endif
  gl_Position = perturb_raster(frame.face_view_proj[face] * vec4(in_position, 1.0));
#elif defined(TECHNIQUE_NV_SWIZZLE)
  // Once for all six faces: viewport f's swizzle permutes (p - light, near) into face f's clip coordinates
  // (backends/common/viewport_swizzle.h says why x, y and w are six_pass's bit for bit and z is the near plane).
#ifdef WRITE_WORLD_POSITION
  world_position = in_position;
#endif
  gl_Position = vec4(in_position - frame.light_position.xyz, frame.light_color.w);
#else
  // Geometry-shader techniques transform per face in the GS.
  gl_Position = vec4(in_position, 1.0);
#if defined(LAYOUT_DUAL_PARABOLOID)
  layer_clip0 = perturb_raster(paraboloid_clip(0, in_position, layer_forward.x));
  layer_clip1 = perturb_raster(paraboloid_clip(1, in_position, layer_forward.y));
#endif
#endif
}
