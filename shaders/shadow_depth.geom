#version 450
// Layered single pass: each triangle is sent to the six faces through gl_Layer.
#if defined(ALL_LIGHTS)
#define POINT_LIGHT_LIST  // every light's view-projections from the list (common.glsl)
#endif
#include "common.glsl"
#include "raster_perturb.glsl"
#if defined(LAYOUT_DUAL_PARABOLOID)
// The vertex stage warped each vertex into both layers (shadow_depth.vert says why there): routed, not recomputed.
layout(location = 1) in vec4 layer_clip0[];
layout(location = 2) in vec4 layer_clip1[];
layout(location = 3) in vec2 layer_forward[];
#endif

// The layout's layer count, from its row (backends/common/layouts.h); the cube's six faces without one.
#if !defined(LAYOUT_LAYERS)
#define LAYOUT_LAYERS 6
#endif

#if defined(ALL_LIGHTS)
// Every light in one pass: invocation i routes each triangle to the faces of lights i and i + 32 that it reaches
// (culled per light and face), light k's face f into layer 6 k + f of every light's layers. 32 invocations is
// the least every device allows (GL_MAX_GEOMETRY_SHADER_INVOCATIONS, maxGeometryShaderInvocations), so 64 lights
// at most (kAllLightsGeometryMaxLights in backends/common/case_config.h).
const int kLightInvocations = 32, kLightsPerInvocation = 2;
layout(triangles, invocations = kLightInvocations) in;
layout(triangle_strip, max_vertices = 36) out;  // 2 lights x 6 faces x 3 vertices
#elif defined(GS_INSTANCED)
layout(triangles, invocations = LAYOUT_LAYERS) in;  // one invocation per face
layout(triangle_strip, max_vertices = 3) out;
#else
layout(triangles) in;                        // the point-shadow tutorial: one invocation loops over the faces
layout(triangle_strip, max_vertices = 18) out;
#endif

#if !defined(DEPTH_ONLY)  // storage hardware_depth: the fragment stage reads nothing
layout(location = 0) out vec3 world_position;
#if defined(ALL_LIGHTS)
layout(location = 1) flat out int shadow_light;  // the light whose layer the primitive goes to
#endif
#endif

#if defined(FACE_CULLING) || defined(ALL_LIGHTS)
// All three vertices beyond one clip plane: the clipper would discard the triangle in this face, so it is not
// emitted at all (the same clip-space values are tested and emitted, so the images cannot change).
bool beyond_one_plane(vec4 c0, vec4 c1, vec4 c2) {
#ifdef VULKAN
  vec3 near_z = vec3(0.0);  // clip z >= 0
#else
  vec3 near_z = -vec3(c0.w, c1.w, c2.w);  // clip z >= -w
#endif
  vec3 x = vec3(c0.x, c1.x, c2.x), y = vec3(c0.y, c1.y, c2.y), z = vec3(c0.z, c1.z, c2.z);
  vec3 w = vec3(c0.w, c1.w, c2.w);
  return all(greaterThan(x, w)) || all(lessThan(x, -w)) || all(greaterThan(y, w)) || all(lessThan(y, -w)) ||
         all(greaterThan(z, w)) || all(lessThan(z, near_z));
}
#endif

void emit_face(int face) {
#if defined(VIEW_FACES)
  // View culling: a face no visible point's lookup reads is not drawn (the draw's mask, gpu::view_faces).
  if ((pass.face_mask & (1u << uint(face))) == 0u) return;
#endif
  vec4 clip[3];
#if defined(LAYOUT_DUAL_PARABOLOID)
  // Layer `face` of the two; the other hemisphere is clipped away (gl_ClipDistance, per vertex below).
  float forward[3];
  for (int i = 0; i < 3; ++i) {
    clip[i] = face == 0 ? layer_clip0[i] : layer_clip1[i];
    forward[i] = face == 0 ? layer_forward[i].x : layer_forward[i].y;
  }
#else
  for (int i = 0; i < 3; ++i) clip[i] = perturb_raster(frame.face_view_proj[face] * gl_in[i].gl_Position);
#endif
#if defined(FACE_CULLING)
  if (beyond_one_plane(clip[0], clip[1], clip[2])) return;
#endif
  for (int i = 0; i < 3; ++i) {
#if defined(LAYOUT_ATLAS)
    gl_ViewportIndex = face;  // layout atlas: face f's tile is viewport f (one layer)
#else
    gl_Layer = face;  // per vertex: outputs are undefined after EmitVertex
#endif
#if !defined(DEPTH_ONLY)
    world_position = gl_in[i].gl_Position.xyz;
#endif
    gl_Position = clip[i];
#if defined(LAYOUT_DUAL_PARABOLOID)
    gl_ClipDistance[0] = forward[i];
#endif
    EmitVertex();
  }
  EndPrimitive();
}

#if defined(ALL_LIGHTS)
// Light k's face f, culled: a triangle beyond one of the face's clip planes would be discarded there anyway.
void emit_light_face(int light, int face) {
  vec4 clip[3];
  for (int i = 0; i < 3; ++i)
    clip[i] = perturb_raster(point_lights[light].face_view_proj[face] * gl_in[i].gl_Position);
  if (beyond_one_plane(clip[0], clip[1], clip[2])) return;
  for (int i = 0; i < 3; ++i) {
    gl_Layer = 6 * light + face;  // per vertex: outputs are undefined after EmitVertex
#if !defined(DEPTH_ONLY)
    world_position = gl_in[i].gl_Position.xyz;
    shadow_light = light;
#endif
    gl_Position = clip[i];
    EmitVertex();
  }
  EndPrimitive();
}
#endif

void main() {
#if defined(ALL_LIGHTS)
  for (int j = 0; j < kLightsPerInvocation; ++j) {
    const int light = gl_InvocationID + j * kLightInvocations;
    // The case's light count, not the list's length(): Vulkan's is the bound range's, which may hold more.
    if (light >= int(frame.lights_info.w)) return;
    for (int face = 0; face < 6; ++face) emit_light_face(light, face);
  }
#elif defined(GS_INSTANCED)
  emit_face(gl_InvocationID);
#else
  for (int layer = 0; layer < LAYOUT_LAYERS; ++layer) emit_face(layer);
#endif
}
