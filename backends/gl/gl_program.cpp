#include "backends/gl/gl_program.h"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "backends/common/driver_log.h"
#include "backends/common/embedded_files.h"
#include "backends/common/shader_variants.h"
#include "backends/common/techniques.h"

namespace omnishadow::gl {
namespace {

const std::string& source_of(const std::string& file) {
  auto it = embedded_files().find(file);
  if (it == embedded_files().end()) throw std::runtime_error("shader file '" + file + "' is not embedded");
  return it->second;
}

void expand(const std::string& file, std::ostringstream& out, int depth) {
  if (depth > 8) throw std::runtime_error("shader include depth exceeded at " + file);
  std::istringstream in(source_of(file));
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.rfind("#include", 0) == 0) {
      size_t open = line.find('"'), close = line.rfind('"');
      if (open == std::string::npos || close <= open) throw std::runtime_error(file + ": bad #include line");
      expand(line.substr(open + 1, close - open - 1), out, depth + 1);
      // Driver messages then give the line in the including file; file numbers in #line are not portable.
      out << "#line " << line_number + 1 << "\n";
    } else {
      out << line << "\n";
    }
  }
}

// A shader's or program's whole info log, one line (driver_log.h): NVIDIA puts the message after a header
// line.
template <typename GetIv, typename GetLog>
std::string info_log(GLuint object, GetIv get_iv, GetLog get_log) {
  GLint length = 0;
  get_iv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<size_t>(length > 0 ? length : 1), '\0');
  get_log(object, length, nullptr, log.data());
  return one_line_log(log);
}

}  // namespace

std::string preprocess_shader(const std::string& file, const std::vector<std::string>& defines) {
  std::ostringstream body;
  expand(file, body, 0);
  std::string text = body.str();
  size_t version_end = text.find('\n');
  if (text.rfind("#version", 0) != 0) throw std::runtime_error(file + ": must start with #version");
  std::string header;
  for (const std::string& d : defines) {
    size_t eq = d.find('=');
    header += "#define " + (eq == std::string::npos ? d : d.substr(0, eq) + " " + d.substr(eq + 1)) + "\n";
  }
  return text.substr(0, version_end + 1) + header + text.substr(version_end + 1);
}

GLuint link_program(const std::vector<ShaderText>& stages) {
  GLuint program = glCreateProgram();
  std::vector<GLuint> shaders;
  auto cleanup = [&] {
    for (GLuint s : shaders) glDeleteShader(s);
  };
  for (const ShaderText& stage : stages) {
    GLuint shader = glCreateShader(stage.type);
    shaders.push_back(shader);
    const char* src = stage.text.c_str();
    glShaderSource(shader, 1, &src, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      std::string log = info_log(shader, glGetShaderiv, glGetShaderInfoLog);
      cleanup();
      glDeleteProgram(program);
      throw std::runtime_error("compiling " + stage.file + " failed: " + log);
    }
    glAttachShader(program, shader);
  }
  glLinkProgram(program);
  cleanup();
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    std::string log = info_log(program, glGetProgramiv, glGetProgramInfoLog);
    glDeleteProgram(program);
    throw std::runtime_error("linking " + stages.front().file + " failed: " + log);
  }
  return program;
}

std::vector<ShaderText> program_texts(const std::vector<ShaderStage>& stages,
                                      const std::vector<std::string>& defines) {
  std::vector<ShaderText> texts;
  for (const ShaderStage& stage : stages)
    texts.push_back({stage.type, stage.file, preprocess_shader(stage.file, defines)});
  return texts;
}

GLuint build_program(const std::vector<ShaderStage>& stages, const std::vector<std::string>& defines) {
  return link_program(program_texts(stages, defines));
}

ProgramSource shadow_program_source(const CaseConfig& c, int subpixel_bits) {
  ProgramSource out;
  const bool mesh = traits(c.technique).stages == ShadowStages::task_mesh;
  // One program, one define list: every stage's defines (the fragment stage's name the storage), each once.
  for (const auto& list : {mesh ? gpu::shadow_mesh_defines(c) : gpu::shadow_vertex_defines(c),
                           gpu::shadow_geometry_defines(c), gpu::shadow_fragment_defines(c)})
    for (const std::string& d : list)
      if (std::find(out.defines.begin(), out.defines.end(), d) == out.defines.end()) out.defines.push_back(d);
  if (c.raster_perturb_steps != 0.0f) {
    char perturb[64];
    std::snprintf(perturb, sizeof perturb, "RASTER_PERTURB_NDC=%.9g",
                  gpu::raster_perturb_ndc(c, subpixel_bits));
    out.defines.push_back(perturb);
  }
  if (mesh && c.emulate_mesh_shader) {  // the task stage's compute program is the backend's own
    out.stages = {{GL_VERTEX_SHADER, gpu::shadow_mesh_files(c).mesh}};
  } else if (mesh) {
    out.stages = {{GL_TASK_SHADER_NV, "shadow_mesh.task"}, {GL_MESH_SHADER_NV, "shadow_mesh.mesh"}};
  } else {
    out.stages = {{GL_VERTEX_SHADER, "shadow_depth.vert"}};
    if (const std::string gs = gpu::shadow_geometry_file(c); !gs.empty())
      out.stages.push_back({GL_GEOMETRY_SHADER, gs});
  }
  out.stages.push_back({GL_FRAGMENT_SHADER, "shadow_depth.frag"});
  return out;
}

}  // namespace omnishadow::gl
