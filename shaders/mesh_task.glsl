// mesh_shader's task stage body, shared by the stage itself (shadow_mesh.task) and its test-only emulation as a
// compute shader (shadow_mesh_task.comp). Each includer defines where an entry goes, store_entry(slot, entry), and
// what ends the workgroup, emit_tasks(task, total).
//
// One invocation per meshlet, kMeshletsPerTask a group. Each meshlet goes on to a mesh workgroup per face it may
// reach: all six, or with FACE_CULLING only those whose frustum its bounding sphere meets. Every light in one pass
// (ALL_LIGHTS): a task workgroup per (group, light), the faces of that light culled always, as the geometry
// shader's one pass culls per light and face.

layout(local_size_x = 32) in;  // kMeshletsPerTask

shared uint face_masks[kMeshletsPerTask];

void main() {
  const uint local = gl_LocalInvocationID.x;
  const uint task = first_task_group() + gl_WorkGroupID.x;
  const uint light = task_light(task);
  const uint meshlet = task_group(task) * kMeshletsPerTask + local;
  uint mask = meshlets[meshlet].triangle_count == 0u ? 0u : 0x3Fu;
#if defined(FACE_CULLING) || defined(ALL_LIGHTS)
  if (mask != 0u) mask &= sphere_face_mask(meshlet_spheres[meshlet], light);
#endif
  face_masks[local] = mask;
  barrier();
  // A fixed order, meshlet by meshlet and face by face, the same every frame and on every device: no atomics.
  uint slot = 0u, total = 0u;
  for (uint k = 0u; k < kMeshletsPerTask; ++k) {
    const uint n = uint(bitCount(face_masks[k]));
    if (k < local) slot += n;
    total += n;
  }
  for (uint f = 0u; f < 6u; ++f)
    if ((mask & (1u << f)) != 0u) store_entry(slot++, meshlet * 8u + f);
  emit_tasks(task, total);
}
