#version 450
// nv_swizzle's geometry stage: a passthrough GS (NV_geometry_shader_passthrough) forwards each triangle untouched and
// only names the viewports that get it (NV_viewport_array2's gl_ViewportMask). Viewport f's swizzle turns the vertex
// stage's (p - light, near) into face f's clip coordinates (backends/common/viewport_swizzle.h), and the
// viewport-relative gl_Layer puts viewport f's copy in layer f.
#extension GL_NV_geometry_shader_passthrough : require
#extension GL_NV_viewport_array2 : require
#include "common.glsl"

layout(triangles) in;
layout(passthrough) in gl_PerVertex { vec4 gl_Position; } gl_in[];
#if !defined(DEPTH_ONLY)  // storage hardware_depth is refused for nv_swizzle; kept for symmetry with shadow_depth.geom
layout(passthrough, location = 0) in vec3 world_position[];
#endif
layout(viewport_relative) out int gl_Layer;

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
  gl_ViewportMask[0] = mask;
  gl_Layer = 0;
}
