#pragma once
// GL side of technique mesh_shader (GL_NV_mesh_shader): the scene's meshlets in shader storage buffers
// (backends/common/meshlets.h), built on the first mesh_shader case of a scene, and the draws.

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
  // One glDrawMeshTasksNV per object: its task groups (first, count).
  void draw(const ObjectDraw& draw) const;
  size_t bytes() const { return data_.bytes(); }

 private:
  gpu::MeshletData data_;
  GLuint scene_vertices_;            // the backend's vertex buffer, not owned
  std::array<GLuint, 4> buffers_{};  // meshlets, spheres, vertices, triangles
};

}  // namespace omnishadow::gl
