// Writes the GL shadow-pass programs of the techniques whose extensions Mesa lacks (nv_swizzle:
// GL_NV_viewport_swizzle and friends; mesh_shader: GL_NV_mesh_shader) as the GL backend would hand them to
// the driver: one file per stage, includes expanded and the variant's defines inserted.
// tests/gl_shaders_glslang.sh compiles each with glslang, so a GLSL error in a path no CI driver can run is
// still caught here. Usage: gl_shader_sources OUT_DIR  (prints the files written, one a line)
#include <filesystem>
#include <fstream>
#include <iostream>

#include "backends/gl/gl_program.h"
#include "tests/nv_program_configs.h"

int main(int argc, char** argv) {
  using namespace omnishadow;
  if (argc != 2) {
    std::cerr << "usage: gl_shader_sources OUT_DIR\n";
    return 2;
  }
  const std::filesystem::path out = argv[1];
  std::filesystem::create_directories(out);
  int written = 0;
  for (const CaseConfig& c : nv_program_configs()) {
    const gl::ProgramSource program = gl::shadow_program_source(c, 8);
    for (const gl::ShaderStage& stage : program.stages) {
      const std::string extension = stage.file.substr(stage.file.rfind('.'));
      const std::filesystem::path file = out / (nv_program_name(c) + extension);
      std::ofstream(file) << gl::preprocess_shader(stage.file, program.defines);
      std::cout << file.string() << "\n";
      ++written;
    }
  }
  return written > 0 ? 0 : 1;
}
