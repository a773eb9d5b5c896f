#version 450
// Test only (--emulate-mesh-shader): mesh_shader's task stage as a compute shader, on any device (the body:
// mesh_task.glsl). One dispatch covers every task workgroup of the scene; workgroup `task` writes its entries
// where the mesh stage's emulation reads them (task * MESH_TASK_ENTRIES onwards) and an indirect draw of the mesh
// workgroups it would launch: `total` instances of kMaxMeshletTriangles * 3 vertices, the first vertex
// task * kMaxMeshletTriangles * 3 (how shadow_mesh_emulation.vert finds its task).
#if defined(ALL_LIGHTS)
#define POINT_LIGHT_LIST  // every light's position and range from the list (common.glsl)
#endif
#include "common.glsl"
#include "raster_perturb.glsl"
#include "mesh_common.glsl"

layout(std430, binding = 11) writeonly buffer EmulatedTaskEntries { uint task_entries[]; };
struct DrawArraysCommand {  // GL's DrawArraysIndirectCommand, Vulkan's VkDrawIndirectCommand
  uint vertex_count;
  uint instance_count;
  uint first_vertex;
  uint first_instance;
};
layout(std430, binding = 12) writeonly buffer EmulatedTaskDraws { DrawArraysCommand task_draws[]; };

void store_entry(uint slot, uint entry) { task_entries[gl_WorkGroupID.x * MESH_TASK_ENTRIES + slot] = entry; }

void emit_tasks(uint task, uint total) {
  const uint n = kEmulatedWorkgroupVertices;
  if (gl_LocalInvocationID.x == 0u) task_draws[task] = DrawArraysCommand(n, total, task * n, 0u);
}

#include "mesh_task.glsl"
