#version 450
// nv_swizzle's geometry stage: a passthrough GS (NV_geometry_shader_passthrough) forwards each triangle untouched and
// only names the viewports that get it (NV_viewport_array2's gl_ViewportMask). Viewport f's swizzle turns the vertex
// stage's (p - light, near) into face f's clip coordinates (backends/common/viewport_swizzle.h), and the
// viewport-relative gl_Layer puts viewport f's copy in layer f. LAYOUT_ATLAS: viewport f is face f's tile of one
// layer, so the mask alone routes each copy and no layer is written.
//
// EMULATE_SWIZZLE (test only, CaseConfig::emulate_nv_swizzle): the same mask, but an ordinary GS emits the triangle
// into each face in it with that face's swizzle applied here (the C++ table, packed into SWIZZLES_01/_23/_45) and
// gl_Layer = face (the atlas: gl_ViewportIndex = face), so a device without the NV extensions runs everything else
// nv_swizzle does.
#if !defined(EMULATE_SWIZZLE)
#extension GL_NV_geometry_shader_passthrough : require
#extension GL_NV_viewport_array2 : require
#endif
#include "common.glsl"

layout(triangles) in;
#if defined(EMULATE_SWIZZLE)
layout(triangle_strip, max_vertices = 18) out;
#if defined(VULKAN)
in gl_PerVertex { vec4 gl_Position; } gl_in[];  // the vertex stage's block (shadow_depth.vert), as below
#endif
#if !defined(DEPTH_ONLY)
layout(location = 0) in vec3 world_position_in[];
layout(location = 0) out vec3 world_position;
#endif
#else
layout(passthrough) in gl_PerVertex { vec4 gl_Position; } gl_in[];
#if !defined(DEPTH_ONLY)  // storage hardware_depth is refused for nv_swizzle; kept for symmetry with shadow_depth.geom
layout(passthrough, location = 0) in vec3 world_position[];
#endif
#if !defined(LAYOUT_ATLAS)
layout(viewport_relative) out int gl_Layer;
#endif
#endif

#if defined(EMULATE_SWIZZLE)
// What viewport f's swizzle does: component c of the source is +-(x, y, z, w)[c / 2], negated for odd c.
float swizzle_component(vec4 v, uint c) { return (c & 1u) != 0u ? -v[c >> 1u] : v[c >> 1u]; }
vec4 apply_face_swizzle(vec4 v, int face) {
  const uint pair = face < 2 ? SWIZZLES_01 : face < 4 ? SWIZZLES_23 : SWIZZLES_45;
  const uint s = (pair >> (12u * uint(face & 1))) & 0xFFFu;
  return vec4(swizzle_component(v, s & 7u), swizzle_component(v, (s >> 3u) & 7u), swizzle_component(v, (s >> 6u) & 7u),
              swizzle_component(v, (s >> 9u) & 7u));
}
#endif

void main() {
  int mask = 0x3F;  // faces +X, -X, +Y, -Y, +Z, -Z: bit f = viewport f = layer f
#if defined(FACE_CULLING)
  // Face f's clip w is its axis (f / 2) with sign + for even f, and its clip x and y are the other two axes up to
  // sign (viewport_swizzle_test checks this against the face matrices): a triangle whose three vertices lie beyond
  // one of the face's planes (|x| <= w, |y| <= w, w >= near) is clipped away there, so its bit is cleared. The
  // values tested are the ones the swizzle emits, so the images cannot change.
  const float near_plane = frame.light_color.w;
  for (int f = 0; f < 6; ++f) {
    const int a = f >> 1, b = (a + 1) % 3, c = (a + 2) % 3;
    const float s = (f & 1) == 0 ? 1.0 : -1.0;
    const vec3 w = s * vec3(gl_in[0].gl_Position[a], gl_in[1].gl_Position[a], gl_in[2].gl_Position[a]);
    const vec3 u = vec3(gl_in[0].gl_Position[b], gl_in[1].gl_Position[b], gl_in[2].gl_Position[b]);
    const vec3 v = vec3(gl_in[0].gl_Position[c], gl_in[1].gl_Position[c], gl_in[2].gl_Position[c]);
    if (all(greaterThan(u, w)) || all(lessThan(u, -w)) || all(greaterThan(v, w)) || all(lessThan(v, -w)) ||
        all(lessThan(w, vec3(near_plane))))
      mask &= ~(1 << f);
  }
#endif
#if defined(VIEW_FACES)
  mask &= int(pass.face_mask);  // view culling: only the faces a visible point's lookup reads (gpu::view_faces)
#endif
#if defined(EMULATE_SWIZZLE)
  for (int f = 0; f < 6; ++f) {
    if ((mask & (1 << f)) == 0) continue;
    for (int i = 0; i < 3; ++i) {
#if defined(LAYOUT_ATLAS)
      gl_ViewportIndex = f;  // face f's tile (per vertex: outputs are undefined after EmitVertex)
#else
      gl_Layer = f;  // per vertex: outputs are undefined after EmitVertex
#endif
#if !defined(DEPTH_ONLY)
      world_position = world_position_in[i];
#endif
      gl_Position = apply_face_swizzle(gl_in[i].gl_Position, f);
      EmitVertex();
    }
    EndPrimitive();
  }
#else
  gl_ViewportMask[0] = mask;
#if !defined(LAYOUT_ATLAS)
  gl_Layer = 0;
#endif
#endif
}
