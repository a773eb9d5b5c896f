// mesh_shader's task and mesh stages: the meshlet buffers (std430 mirrors of backends/common/meshlets.h; change both
// together) and what both stages share. Vulkan: GL_EXT_mesh_shader; GL: GL_NV_mesh_shader, whose different
// spellings the two stage files choose between.

const uint kMeshletsPerTask = 32u;       // gpu::kMeshletsPerTask: the task stage's workgroup
const uint kMaxMeshletVertices = 64u;    // gpu::kMaxMeshletVertices
const uint kMaxMeshletTriangles = 124u;  // gpu::kMaxMeshletTriangles
const uint kVertexFloats = 9u;           // scene::Vertex: position, normal, colour (gpu_layout.h asserts it)

struct Meshlet {
  uint vertex_offset;
  uint triangle_offset;
  uint vertex_count;
  uint triangle_count;  // 0: padding up to the next task group
};
layout(std430, binding = 4) readonly buffer Meshlets { Meshlet meshlets[]; };
layout(std430, binding = 5) readonly buffer MeshletSpheres { vec4 meshlet_spheres[]; };  // centre, radius (world)
layout(std430, binding = 6) readonly buffer MeshletVertices { uint meshlet_vertices[]; };  // scene vertex indices
layout(std430, binding = 7) readonly buffer MeshletTriangles { uint meshlet_triangles[]; };  // 3 x 8-bit corners
layout(std430, binding = 8) readonly buffer SceneVertices { float scene_vertices[]; };

// One entry per (meshlet, face) the task stage sends on: meshlet * 8 + face.
#define MESH_TASK_ENTRIES (kMeshletsPerTask * 6u)

vec3 scene_position(uint vertex) {
  const uint base = vertex * kVertexFloats;
  return vec3(scene_vertices[base], scene_vertices[base + 1u], scene_vertices[base + 2u]);
}

// The task stage's first group of this draw: Vulkan pushes it; GL's glDrawMeshTasksNV(first, count) starts
// gl_WorkGroupID.x at it already.
uint first_task_group() {
#ifdef VULKAN
  return pass.first_task;
#else
  return 0u;
#endif
}
