#pragma once
// GL side of technique mesh_shader (GL_NV_mesh_shader): the scene's meshlets in shader storage buffers
// (backends/common/meshlets.h), built on the first mesh_shader case of a scene, and the draws; and its
// test-only emulation (--emulate-mesh-shader): the task stage's compute dispatch and the mesh stage's
// indirect draws.

#include <epoxy/gl.h>

#include <array>
#include <vector>

#include "backends/common/meshlets.h"
#include "backends/common/techniques.h"
#include "scenes/scene.h"

namespace omnishadow::gl {

class GlMeshPass {
 public:
  GlMeshPass(const gpu::MeshletData& meshlets, GLuint scene_vertex_buffer);
  ~GlMeshPass();
  GlMeshPass(const GlMeshPass&) = delete;
  GlMeshPass& operator=(const GlMeshPass&) = delete;

  // Binds the storage buffers to shaders/mesh_common.glsl's binding points.
  void bind() const;
  // One glDrawMeshTasksNV per object: its task workgroups, one per task group and light (lights: 1, or every
  // light of the case in one pass).
  void draw(const ObjectDraw& d, uint32_t lights) const;
  // The emulation: task_program (shaders/shadow_mesh_task.comp) over every task workgroup of the scene, its
  // entries and draws into buffers sized here; then each object's workgroups as indirect draws.
  void emulate_tasks(GLuint task_program, uint32_t lights);
  void draw_emulated(const ObjectDraw& d, uint32_t lights) const;
  // The moving casters' meshlet spheres where the scene's vertices are posed now (the task stage culls by
  // them).
  void update_spheres(const scene::Scene& posed);
  size_t bytes() const { return data_.bytes(); }

 private:
  gpu::MeshletData data_;
  GLuint scene_vertices_;             // the backend's vertex buffer, not owned
  std::array<GLuint, 4> buffers_{};   // meshlets, spheres, vertices, triangles
  std::array<GLuint, 2> emulated_{};  // the emulation's task entries and indirect draws
  uint32_t emulated_tasks_ = 0;       // the task workgroups they hold
};

}  // namespace omnishadow::gl
