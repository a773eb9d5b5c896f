#include "backends/gl/gl_mesh_pass.h"

#include <stdexcept>
#include <string>

#include "backends/common/gpu_layout.h"

namespace omnishadow::gl {
namespace {

template <typename T>
GLuint storage_buffer(const std::vector<T>& data) {
  GLuint b = 0;
  glCreateBuffers(1, &b);
  // An empty scene still binds a buffer: zero-sized storage is an error, so keep 16 bytes.
  const size_t bytes = data.empty() ? 16 : data.size() * sizeof(T);
  glNamedBufferStorage(b, static_cast<GLsizeiptr>(bytes), data.empty() ? nullptr : data.data(), 0);
  return b;
}

}  // namespace

GlMeshPass::GlMeshPass(const gpu::MeshletData& meshlets, GLuint scene_vertex_buffer)
    : data_(meshlets), scene_vertices_(scene_vertex_buffer) {
  buffers_ = {storage_buffer(data_.meshlets), storage_buffer(data_.spheres), storage_buffer(data_.vertices),
              storage_buffer(data_.triangles)};
  if (glGetError() == GL_OUT_OF_MEMORY) {
    glDeleteBuffers(static_cast<GLsizei>(buffers_.size()), buffers_.data());
    throw std::runtime_error("GL_OUT_OF_MEMORY uploading " + std::to_string(data_.bytes()) +
                             " bytes of meshlets");
  }
}

GlMeshPass::~GlMeshPass() { glDeleteBuffers(static_cast<GLsizei>(buffers_.size()), buffers_.data()); }

void GlMeshPass::bind() const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMeshletsBinding, buffers_[0]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMeshletSpheresBinding, buffers_[1]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMeshletVerticesBinding, buffers_[2]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMeshletTrianglesBinding, buffers_[3]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kSceneVerticesBinding, scene_vertices_);
}

void GlMeshPass::draw(const ObjectDraw& d) const {
  const gpu::ObjectMeshlets& o = data_.objects[d.object];
  if (o.task_count > 0) glDrawMeshTasksNV(o.first_task, o.task_count);
}

}  // namespace omnishadow::gl
