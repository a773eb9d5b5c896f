#include "backends/gl/gl_cube_summary.h"

#include <stdexcept>
#include <string>
#include <vector>

#include "backends/common/cube_summary.h"

namespace omnishadow::gl {

void read_cube_summary(GLuint program, GLuint layers, GLuint sampler, int cube_size, Images& img) {
  const size_t bytes = cube::summary_buffer_bytes(cube_size);
  GLuint buffer = 0;
  glCreateBuffers(1, &buffer);
  glNamedBufferStorage(buffer, static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
  const GLuint zero = 0;
  glClearNamedBufferData(buffer, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);  // the sums start at 0
  glUseProgram(program);
  glUniform1i(0, cube_size);
  glUniform1i(1, cube_sample_stride(cube_size));
  // Unit 0 and binding 1 are the compute program's own; every pass binds its textures and blocks again.
  glBindTextureUnit(0, layers);
  glBindSampler(0, sampler);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffer);
  // 16 x 16 invocations a group, each 16 rows of a column (shaders/cube_summary.comp).
  const GLuint columns = static_cast<GLuint>((cube_size + 15) / 16),
               rows = static_cast<GLuint>((cube_size + 255) / 256);
  glDispatchCompute(columns, rows, 6);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<unsigned char> host(bytes);
  glGetNamedBufferSubData(buffer, 0, static_cast<GLsizeiptr>(bytes), host.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
  glDeleteBuffers(1, &buffer);
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR)
    throw std::runtime_error("GL error " + std::to_string(error) + " in the cube summary");
  cube::unpack_summary(host.data(), cube_size, img);
}

}  // namespace omnishadow::gl
