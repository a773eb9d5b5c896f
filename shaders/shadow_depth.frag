#version 450
// Shadow pass fragment stage: what is stored is a distance from the light, never projective depth.
#if defined(ALL_LIGHTS)
#define POINT_LIGHT_LIST  // the primitive's light from the list (common.glsl), not frame.light_*
#endif
#include "common.glsl"
#include "moments.glsl"

#if !defined(STORAGE_HARDWARE_DEPTH) && defined(TECHNIQUE_MESH_SHADER) && !defined(EMULATE_MESH_SHADER)
layout(location = 0) in MeshVertex {  // the mesh stage's per-vertex block
  vec3 world_position;
#if defined(ALL_LIGHTS)
  flat int shadow_light;
#endif
};
#elif !defined(STORAGE_HARDWARE_DEPTH)
layout(location = 0) in vec3 world_position;
#if defined(ALL_LIGHTS)
layout(location = 1) flat in int shadow_light;
#endif
#endif

#if defined(STORAGE_R32F_DISTANCE)
layout(location = 0) out float out_distance;  // the multipass tutorial: world units in an R32F cube cleared to FLT_MAX
#elif defined(MOMENTS_STORAGE)
layout(location = 0) out vec4 out_moments;  // the moments of the z written as depth (the format keeps what it has)
#endif

void main() {
#if defined(ALL_LIGHTS) && !defined(STORAGE_HARDWARE_DEPTH)
  g_light = shadow_light;
#endif
#if defined(FAR_BY_FRAGMENT)
  // nv_swizzle's reversed depth has no far plane (backends/common/viewport_swizzle.h): the fragments beyond the
  // one the face projection clips at (clip w, the distance along the face's axis, past far) are dropped here, so
  // that a light whose range ends inside the scene stores nothing there, as six_pass does. gl_FragCoord.w is
  // 1 / clip w.
  if (gl_FragCoord.w * light_far() < 1.0) discard;
#endif
#if defined(STORAGE_R32F_DISTANCE)
  out_distance = length(world_position - light_position());
#elif defined(STORAGE_LINEAR_DEPTH)
  gl_FragDepth = length(world_position - light_position()) / light_far();  // the point-shadow tutorial: distance / far
#elif defined(MOMENTS_STORAGE)
  // One z for both: the checks rebuild the moments from the depth the same fragment wrote.
  float z = length(world_position - light_position()) / light_far();
  gl_FragDepth = z;
  out_moments = distance_moments(z);
#endif
  // STORAGE_HARDWARE_DEPTH: nothing written; the rasteriser's projective depth is what is stored.
}
