#include "backends/gl/gl_mesh_pass.h"

#include <stdexcept>
#include <string>

#include "backends/common/gpu_layout.h"

namespace omnishadow::gl {
namespace {

template <typename T>
GLuint storage_buffer(const std::vector<T>& data, GLbitfield flags = 0) {
  GLuint b = 0;
  glCreateBuffers(1, &b);
  // An empty scene still binds a buffer: zero-sized storage is an error, so keep 16 bytes.
  const size_t bytes = data.empty() ? 16 : data.size() * sizeof(T);
  glNamedBufferStorage(b, static_cast<GLsizeiptr>(bytes), data.empty() ? nullptr : data.data(), flags);
  return b;
}

// The emulation's draws: one DrawArraysIndirectCommand per task workgroup (shaders/shadow_mesh_task.comp).
constexpr GLsizeiptr kDrawCommandBytes = 4 * sizeof(GLuint);

}  // namespace

GlMeshPass::GlMeshPass(const gpu::MeshletData& meshlets, GLuint scene_vertex_buffer)
    : data_(meshlets), scene_vertices_(scene_vertex_buffer) {
  // The spheres are rewritten where casters move (update_spheres).
  buffers_ = {storage_buffer(data_.meshlets), storage_buffer(data_.spheres, GL_DYNAMIC_STORAGE_BIT),
              storage_buffer(data_.vertices), storage_buffer(data_.triangles)};
  if (glGetError() == GL_OUT_OF_MEMORY) {
    glDeleteBuffers(static_cast<GLsizei>(buffers_.size()), buffers_.data());
    throw std::runtime_error("GL_OUT_OF_MEMORY uploading " + std::to_string(data_.bytes()) +
                             " bytes of meshlets");
  }
}

GlMeshPass::~GlMeshPass() {
  glDeleteBuffers(static_cast<GLsizei>(buffers_.size()), buffers_.data());
  glDeleteBuffers(static_cast<GLsizei>(emulated_.size()), emulated_.data());
}

void GlMeshPass::bind() const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMeshletsBinding, buffers_[0]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMeshletSpheresBinding, buffers_[1]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMeshletVerticesBinding, buffers_[2]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kMeshletTrianglesBinding, buffers_[3]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kSceneVerticesBinding, scene_vertices_);
}

// An object's task groups F .. F + n - 1 are workgroups F K .. (F + n) K - 1 for K lights
// (shaders/mesh_common.glsl, task_group and task_light).
void GlMeshPass::draw(const ObjectDraw& d, uint32_t lights) const {
  const gpu::ObjectMeshlets& o = data_.objects[d.object];
  if (o.task_count > 0) glDrawMeshTasksNV(o.first_task * lights, o.task_count * lights);
}

void GlMeshPass::emulate_tasks(GLuint task_program, uint32_t lights) {
  const uint32_t tasks = static_cast<uint32_t>(data_.meshlets.size() / gpu::kMeshletsPerTask) * lights;
  if (tasks == 0) return;
  if (tasks > emulated_tasks_) {
    glDeleteBuffers(static_cast<GLsizei>(emulated_.size()), emulated_.data());
    glCreateBuffers(static_cast<GLsizei>(emulated_.size()), emulated_.data());
    glNamedBufferStorage(emulated_[0], GLsizeiptr(tasks) * gpu::kMeshletsPerTask * 6 * sizeof(GLuint),
                         nullptr, 0);
    glNamedBufferStorage(emulated_[1], GLsizeiptr(tasks) * kDrawCommandBytes, nullptr, 0);
    emulated_tasks_ = tasks;
  }
  // The previous light's draws read these buffers: their reads are done before the dispatch rewrites them.
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kEmulatedTaskEntriesBinding, emulated_[0]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gpu::kEmulatedTaskDrawsBinding, emulated_[1]);
  glUseProgram(task_program);
  glDispatchCompute(tasks, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);  // the draws read both
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, emulated_[1]);
}

void GlMeshPass::draw_emulated(const ObjectDraw& d, uint32_t lights) const {
  const gpu::ObjectMeshlets& o = data_.objects[d.object];
  if (o.task_count == 0) return;
  const GLintptr offset = GLintptr(o.first_task) * lights * kDrawCommandBytes;
  glMultiDrawArraysIndirect(GL_TRIANGLES, reinterpret_cast<const void*>(offset),
                            GLsizei(o.task_count * lights), 0);
}

void GlMeshPass::update_spheres(const scene::Scene& posed) {
  for (const gpu::MeshletRange& r : gpu::update_moving_spheres(posed, data_))
    glNamedBufferSubData(buffers_[1], GLintptr(r.first) * GLintptr(sizeof(glm::vec4)),
                         GLsizeiptr(r.count) * GLsizeiptr(sizeof(glm::vec4)), &data_.spheres[r.first]);
}

}  // namespace omnishadow::gl
