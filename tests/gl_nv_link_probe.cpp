// Compiles and links, on this machine's GL driver, every GL program of the techniques that exist for NVIDIA
// GPUs (nv_swizzle: NV_geometry_shader_passthrough and friends; mesh_shader: NV_mesh_shader) exactly as the
// GL backend builds them, and prints each result with the driver's whole log. Then it links nv_swizzle's
// passthrough stage in the forms that other GL code that runs on NVIDIA writes it, so one run on an NVIDIA
// GPU says which form its compiler takes (NVIDIA's linker refused the spec's own form with "max_vertices
// layout qualifier must be declared" at fb5456a). gpu_acceptance.sh's singlepass step runs it first. Mesa
// lacks the extensions: exit 77 with the reason there (ctest runs it only as a build check). Usage:
// gl_nv_link_probe   (exit 0: every shipped program linked; 1: one did not; 77: extensions missing)
#include <epoxy/gl.h>

#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "backends/gl/egl_context.h"
#include "backends/gl/gl_program.h"
#include "tests/nv_program_configs.h"

namespace {

using namespace omnishadow;

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at == std::string::npos)
    throw std::runtime_error("probe form: '" + from + "' not in the passthrough stage");
  return text.replace(at, from.size(), to);
}

bool try_link(const std::string& name, const std::vector<gl::ShaderText>& stages) {
  try {
    glDeleteProgram(gl::link_program(stages));
    std::printf("linked: %s\n", name.c_str());
    return true;
  } catch (const std::exception& e) {
    std::printf("FAILED: %s: %s\n", name.c_str(), e.what());
    return false;
  }
}

// The passthrough stage in other spellings, each a function of the shipped text (linear_depth, no culling:
// the stage reads none of its inputs, so an anonymous gl_PerVertex is legal there).
void probe_passthrough_forms() {
  const gl::ProgramSource source =
      gl::shadow_program_source(nv_program_config(Technique::nv_swizzle, Storage::linear_depth, false), 8);
  const std::vector<gl::ShaderText> shipped = gl::program_texts(source.stages, source.defines);
  using Edit = std::function<std::string(std::string)>;
  const Edit invocations = [](std::string t) {
    return replaced(t, "layout(triangles) in;", "layout(invocations = 1, triangles) in;");
  };
  const Edit anonymous = [](std::string t) {
    return replaced(t, "vec4 gl_Position; } gl_in[];", "vec4 gl_Position; };");
  };
  const Edit whole_block = [](std::string t) {
    return replaced(t, "{ vec4 gl_Position; }",
                    "{ vec4 gl_Position; float gl_PointSize; float gl_ClipDistance[]; }");
  };
  const std::vector<std::pair<std::string, std::vector<Edit>>> forms = {
      {"passthrough form: invocations = 1 declared", {invocations}},
      {"passthrough form: gl_PerVertex redeclared without the gl_in instance name", {anonymous}},
      {"passthrough form: gl_PerVertex with gl_PointSize and gl_ClipDistance[]", {whole_block}},
      {"passthrough form: all three (an emulator's GLSL that runs on NVIDIA GL)",
       {invocations, whole_block, anonymous}},
  };
  for (const auto& [name, edits] : forms) {
    std::vector<gl::ShaderText> stages = shipped;
    for (gl::ShaderText& s : stages)
      if (s.type == GL_GEOMETRY_SHADER)
        for (const Edit& e : edits) s.text = e(s.text);
    try_link(name, stages);
  }
}

}  // namespace

int main() {
  try {
    gl::EglContext context("surfaceless", 0, false);
    std::printf("GL %s | %s\n", reinterpret_cast<const char*>(glGetString(GL_VERSION)),
                reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    std::string missing;
    for (const char* ext : {"GL_NV_viewport_swizzle", "GL_NV_viewport_array2",
                            "GL_NV_geometry_shader_passthrough", "GL_NV_mesh_shader"})
      if (!epoxy_has_gl_extension(ext)) missing += std::string(missing.empty() ? "" : ", ") + ext;
    if (!missing.empty()) {
      std::printf("SKIP: %s missing on this driver: nothing to link\n", missing.c_str());
      return 77;
    }
    bool all = true;
    for (const CaseConfig& c : nv_program_configs()) {
      const gl::ProgramSource source = gl::shadow_program_source(c, 8);
      all &= try_link(nv_program_name(c), gl::program_texts(source.stages, source.defines));
    }
    probe_passthrough_forms();
    std::printf("%s\n", all ? "every shipped program linked" : "a shipped program did not link");
    return all ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("FAILED: %s\n", e.what());
    return 1;
  }
}
