#pragma once
// Technique mesh_shader's input: every object's triangles as meshlets (meshoptimizer's clusters of at most
// kMaxMeshletVertices vertices and kMaxMeshletTriangles triangles), the storage buffers both APIs' task and
// mesh stages read (shaders/mesh_common.glsl mirrors these layouts: std430, change both together).
//
// Task workgroups: one per kMeshletsPerTask meshlets. Each object's meshlets start at a multiple of
// kMeshletsPerTask (the gap is padded with empty meshlets, which the task stage skips), so drawing an object
// is "task groups first_task .. first_task + task_count - 1" with no per-draw meshlet count.
//
// Positions are not copied: meshlet_vertices index the scene's own vertex buffer (scene::Vertex, read as
// floats by the mesh stage), so the mesh stage transforms exactly the floats six_pass's vertex stage does.
// Vertices are welded by position within an object first (the scenes are unindexed triangle lists); a welded
// vertex has the same position bits, so the clip coordinates cannot change.

#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "scenes/scene.h"

namespace omnishadow::gpu {

inline constexpr uint32_t kMaxMeshletVertices = 64;
inline constexpr uint32_t kMaxMeshletTriangles = 124;  // meshoptimizer wants a multiple of 4
inline constexpr uint32_t kMeshletsPerTask = 32;       // the task stage's workgroup size

struct Meshlet {
  uint32_t vertex_offset;    // into MeshletData::vertices
  uint32_t triangle_offset;  // into MeshletData::triangles
  uint32_t vertex_count;
  uint32_t triangle_count;  // 0: padding
};

struct ObjectMeshlets {
  uint32_t first_task;  // first task group: meshlets first_task * kMeshletsPerTask onwards
  uint32_t task_count;
};

struct MeshletData {
  std::vector<Meshlet> meshlets;   // a multiple of kMeshletsPerTask
  std::vector<glm::vec4> spheres;  // per meshlet: centre (world units) and a radius that contains every
                                   // vertex (computed in double, rounded up); zero for padding
  std::vector<uint32_t> vertices;  // indices into Scene::vertices
  std::vector<uint32_t>
      triangles;  // per triangle: its three local vertex indices, 8 bits each (bits 0-7, 8-15,
                  // 16-23), in the scene's winding order (back-face culling sees the same triangle)
  std::vector<ObjectMeshlets> objects;  // per Scene::objects entry
  size_t bytes() const;
};

MeshletData build_meshlets(const scene::Scene& scene);

// What a device's launch limits refuse of mesh_shader over these meshlets, with `lights` task workgroups per
// meshlet group (every light in one pass; 1 per light): natively, each object's workgroups in one launch
// (launch_limit, named launch_name: GL_MAX_DRAW_MESH_TASKS_COUNT_NV, maxTaskWorkGroupCount[0]); emulated,
// every workgroup of the scene in one compute dispatch (dispatch_limit, dispatch_name). Empty: nothing
// refused.
std::string mesh_launch_refusal(const MeshletData& data, uint32_t lights, bool emulated,
                                uint64_t launch_limit, const std::string& launch_name,
                                uint64_t dispatch_limit, const std::string& dispatch_name);

// A range of meshlets, [first, first + count).
struct MeshletRange {
  uint32_t first;
  uint32_t count;
};
// The moving casters' meshlet spheres recomputed from the scene's vertices as posed now (the same rule as
// build_meshlets': the task stage's culling stays conservative at every frame); returns the ranges rewritten,
// one per moving object, for the backends to upload.
std::vector<MeshletRange> update_moving_spheres(const scene::Scene& posed, MeshletData& data);

}  // namespace omnishadow::gpu
