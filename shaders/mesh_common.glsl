// mesh_shader's task and mesh stages: the meshlet buffers (std430 mirrors of backends/common/meshlets.h; change both
// together) and what both stages share. Vulkan: GL_EXT_mesh_shader; GL: GL_NV_mesh_shader, whose different
// spellings the two stage files choose between. The test-only emulation (EMULATE_MESH_SHADER: the task stage as a
// compute shader, the mesh stage as a vertex shader, shadow_mesh_task.comp and shadow_mesh_emulation.vert) runs
// the same functions below.

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
// The emulation (EMULATE_MESH_SHADER): a mesh workgroup is an instance of this many vertices, three a triangle.
const uint kEmulatedWorkgroupVertices = kMaxMeshletTriangles * 3u;

// A task workgroup's meshlet group and light. Per light: the group, the light the frame uniforms hold. Every light
// in one pass (ALL_LIGHTS): task group * K + light, for the K lights of the case (the frame's lights_info.w; the
// list's length() is the bound range's on Vulkan), so that an object's task workgroups stay contiguous: its groups
// F .. F + n - 1 are workgroups F K .. (F + n) K - 1.
uint task_light_count() {
#if defined(ALL_LIGHTS)
  return uint(frame.lights_info.w);
#else
  return 1u;
#endif
}
uint task_group(uint task) { return task / task_light_count(); }
uint task_light(uint task) { return task % task_light_count(); }

// The light's position, near and far (world units): light k's record with every light in one pass.
vec3 task_light_position(uint light) {
#if defined(ALL_LIGHTS)
  return point_lights[light].position_far.xyz;
#else
  return frame.light_position.xyz;
#endif
}
vec2 task_light_near_far(uint light) {
#if defined(ALL_LIGHTS)
  return vec2(point_lights[light].colour_near.w, point_lights[light].position_far.w);
#else
  return vec2(frame.light_color.w, frame.light_position.w);
#endif
}

// Faces of the light whose frustum the sphere may meet. Face f looks along axis f / 2 (sign + for even f: the face
// order of cube_faces.h); its frustum is |u| <= w, |v| <= w, near <= w <= far in the light-relative coordinates, w
// along its axis and u, v the other two. A plane w - u = 0 has normal length sqrt 2: the sphere is beyond it when
// w - u < -r sqrt 2. The slack covers the float rounding of the centre's light-relative coordinates (a few ulps of
// the larger of the two magnitudes), so culling never drops a face the sphere reaches.
uint sphere_face_mask(vec4 sphere, uint light) {
  const vec3 position = task_light_position(light);
  const vec2 near_far = task_light_near_far(light);
  const vec3 c = sphere.xyz - position;
  const float magnitude = max(max(abs(sphere.x), abs(sphere.y)), max(abs(sphere.z), 0.0)) +
                          max(max(abs(position.x), abs(position.y)), abs(position.z));
  const float r = sphere.w * (1.0 + 1e-6) + 8.0 * 1.2e-7 * magnitude;
  uint mask = 0u;
  for (int f = 0; f < 6; ++f) {
    const int a = f >> 1;
    const float w = (f & 1) == 0 ? c[a] : -c[a];
    const float u = c[(a + 1) % 3], v = c[(a + 2) % 3];
    const float reach = -r * 1.41421357;
    const bool beyond = w - u < reach || w + u < reach || w - v < reach || w + v < reach || w < near_far.x - r ||
                        w > near_far.y + r;
    if (!beyond) mask |= 1u << f;
  }
  return mask;
}

// Light `light`'s face `face` clip position of a scene point: exactly six_pass's vertex-stage expression (the
// frame's face matrices per light, the list's with every light in one pass, as the geometry shader's one pass).
vec4 meshlet_clip(uint light, int face, vec3 p) {
#if defined(ALL_LIGHTS)
  return perturb_raster(point_lights[light].face_view_proj[face] * vec4(p, 1.0));
#else
  return perturb_raster(frame.face_view_proj[face] * vec4(p, 1.0));
#endif
}

// The layer light `light`'s face `face` goes to: light k's face f is layer 6 k + f of every light's layers.
int meshlet_layer(uint light, int face) { return 6 * int(light) + face; }

// Triangle i of meshlet m: its three local vertex indices (3 x 8 bits, meshlets.h).
uvec3 meshlet_corners(Meshlet m, uint i) {
  const uint corner_bytes = meshlet_triangles[m.triangle_offset + i];
  return uvec3(corner_bytes & 0xFFu, (corner_bytes >> 8u) & 0xFFu, (corner_bytes >> 16u) & 0xFFu);
}

vec3 scene_position(uint vertex) {
  const uint base = vertex * kVertexFloats;
  return vec3(scene_vertices[base], scene_vertices[base + 1u], scene_vertices[base + 2u]);
}

// The task stage's first workgroup of this draw: Vulkan pushes it (the object's first task group, times K with every
// light in one pass); GL's glDrawMeshTasksNV(first, count) starts gl_WorkGroupID.x at it already, as the
// emulation's one dispatch over every object does.
uint first_task_group() {
#if defined(VULKAN) && !defined(EMULATE_MESH_SHADER)
  return pass.first_task;
#else
  return 0u;
#endif
}
