#version 450
// Test only (--emulate-mesh-shader): mesh_shader's mesh stage as a vertex shader, on any device that writes
// gl_Layer from the vertex stage (vs_layer's feature). Each indirect draw shadow_mesh_task.comp wrote is one task
// workgroup: instance i is the mesh workgroup of its entry i, vertex 3 t + c corner c of the meshlet's triangle t.
// A triangle past the meshlet's count goes outside every clip volume (nothing drawn). The positions, layers and
// outputs are what shadow_mesh.mesh computes, through the same functions (mesh_common.glsl).
#extension GL_ARB_shader_viewport_layer_array : require
#if defined(ALL_LIGHTS)
#define POINT_LIGHT_LIST  // every light's view-projections from the list (common.glsl)
#endif
#include "common.glsl"
#include "raster_perturb.glsl"
#include "mesh_common.glsl"

layout(std430, binding = 11) readonly buffer EmulatedTaskEntries { uint task_entries[]; };

#ifdef VULKAN
#define VERTEX_INDEX gl_VertexIndex      // firstVertex included
#define INSTANCE_INDEX gl_InstanceIndex  // firstInstance (0) included
#else
#define VERTEX_INDEX gl_VertexID  // glDrawArrays*'s first included
#define INSTANCE_INDEX gl_InstanceID
#endif

// The vertex techniques' outputs (shadow_depth.vert's): Vulkan's validation layer takes a block here for
// another type than the fragment stage's vec3 at location 0.
#if !defined(DEPTH_ONLY)
layout(location = 0) out vec3 world_position;
#if defined(ALL_LIGHTS)
layout(location = 1) flat out int shadow_light;
#endif
#endif

void main() {
  const uint task = uint(VERTEX_INDEX) / kEmulatedWorkgroupVertices;
  const uint corner = uint(VERTEX_INDEX) % kEmulatedWorkgroupVertices;
  const uint entry = task_entries[task * MESH_TASK_ENTRIES + uint(INSTANCE_INDEX)];
  const uint meshlet = entry >> 3u;
  const int face = int(entry & 7u);
  const uint light = task_light(task);
  const Meshlet m = meshlets[meshlet];
  const uint triangle = corner / 3u;
  gl_Layer = meshlet_layer(light, face);
#if !defined(DEPTH_ONLY)
#if defined(ALL_LIGHTS)
  shadow_light = int(light);
#endif
  world_position = vec3(0.0);
#endif
  if (triangle >= m.triangle_count) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // beyond x <= w on both APIs: the triangle is clipped whole
    return;
  }
  const uint local_vertex = meshlet_corners(m, triangle)[corner % 3u];
  const vec3 p = scene_position(meshlet_vertices[m.vertex_offset + local_vertex]);
  gl_Position = meshlet_clip(light, face, p);
#if !defined(DEPTH_ONLY)
  world_position = p;
#endif
}
