#pragma once
// GL programs built from the shared GLSL in shaders/: includes resolved here (glslc resolves them for
// Vulkan), variant macros inserted after #version.

#include <epoxy/gl.h>

#include <string>
#include <vector>

#include "backends/common/case_config.h"

namespace omnishadow::gl {

struct ShaderStage {
  GLenum type;       // GL_VERTEX_SHADER, ...
  std::string file;  // name in shaders/, e.g. "shadow_depth.vert"
};

// Source text of `file` with #include "x" expanded and `defines` (NAME or NAME=VALUE) added after #version.
std::string preprocess_shader(const std::string& file, const std::vector<std::string>& defines);

// A stage's text as handed to the driver.
struct ShaderText {
  GLenum type;
  std::string file;  // the name errors give
  std::string text;
};
std::vector<ShaderText> program_texts(const std::vector<ShaderStage>& stages,
                                      const std::vector<std::string>& defines);

// Compiles and links; throws std::runtime_error with the file name and the driver's whole log on one line
// (backends/common/driver_log.h).
GLuint link_program(const std::vector<ShaderText>& stages);
GLuint build_program(const std::vector<ShaderStage>& stages, const std::vector<std::string>& defines);

// The shadow pass's program for a case: its stages (vertex [+ geometry] or task + mesh, then fragment) and
// one define list for all of them (the union of the stages' variant defines, as GL compiles them).
struct ProgramSource {
  std::vector<ShaderStage> stages;
  std::vector<std::string> defines;
};
ProgramSource shadow_program_source(const CaseConfig& c, int subpixel_bits);

}  // namespace omnishadow::gl
