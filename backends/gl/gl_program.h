#pragma once
// GL programs built from the shared GLSL in shaders/: includes resolved here (glslc resolves them for Vulkan),
// variant macros inserted after #version.

#include <epoxy/gl.h>

#include <string>
#include <vector>

namespace omnishadow::gl {

struct ShaderStage {
  GLenum type;       // GL_VERTEX_SHADER, ...
  std::string file;  // name in shaders/, e.g. "shadow_depth.vert"
};

// Source text of `file` with #include "x" expanded and `defines` (NAME or NAME=VALUE) added after #version.
std::string preprocess_shader(const std::string& file, const std::vector<std::string>& defines);

// Compiles and links; throws std::runtime_error with the file name and the first line of the driver's log.
GLuint build_program(const std::vector<ShaderStage>& stages, const std::vector<std::string>& defines);

}  // namespace omnishadow::gl
