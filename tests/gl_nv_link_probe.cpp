// Compiles and links, on this machine's GL driver, every GL program of the techniques that exist for NVIDIA
// GPUs (nv_swizzle: NV_geometry_shader_passthrough and friends; mesh_shader: NV_mesh_shader) exactly as the
// GL backend builds them, and prints each result with the driver's whole log. Then it links nv_swizzle's
// passthrough stage in other spellings, and three self-contained passthrough programs (the extension's own
// example first), in a core and in a compatibility context, printing every compile log (warnings too): one
// run on an NVIDIA GPU says which form its compiler takes (NVIDIA's linker refused the shipped form with
// "max_vertices layout qualifier must be declared" at fb5456a and c530e20, although the extension forbids
// max_vertices in a passthrough stage). gpu_acceptance.sh's singlepass step runs it first. Mesa lacks the
// extensions: exit 77 with the reason there. Usage:
//   gl_nv_link_probe                 exit 0: every shipped program linked; 1: one did not; 77: extensions
//   missing gl_nv_link_probe --check-forms   no GL: exit 1 when a form's edit no longer finds its text in the
//   shipped stages
#include <epoxy/gl.h>

#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "backends/gl/egl_context.h"
#include "backends/gl/gl_passthrough.h"
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

std::string one_line(std::string log) {
  for (char& c : log)
    if (c == '\n' || c == '\r') c = ' ';
  while (!log.empty() && (log.back() == ' ' || log.back() == '\0')) log.pop_back();
  return log;
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

// What the compiler says of each stage that compiles: a driver that takes a qualifier it does not honour may
// warn.
void print_compile_logs(const std::string& name, const std::vector<gl::ShaderText>& stages) {
  for (const gl::ShaderText& stage : stages) {
    const GLuint shader = glCreateShader(stage.type);
    const char* src = stage.text.c_str();
    glShaderSource(shader, 1, &src, nullptr);
    glCompileShader(shader);
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    if (length > 1) {
      std::string log(static_cast<size_t>(length), '\0');
      glGetShaderInfoLog(shader, length, nullptr, log.data());
      std::printf("compile log: %s %s: %s\n", name.c_str(), stage.file.c_str(), one_line(log).c_str());
    }
    glDeleteShader(shader);
  }
}

using Edit = std::function<std::string(std::string)>;
struct StageEdit {
  GLenum stage;
  Edit edit;
};

Edit swap(const std::string& from, const std::string& to) {
  return [from, to](std::string t) { return replaced(std::move(t), from, to); };
}

// The passthrough stage in other spellings, each a function of the shipped text (linear_depth, no culling:
// the stage reads none of its inputs, so an anonymous gl_PerVertex is legal there). One form that links names
// what NVIDIA's compiler needs; the compatibility profile says whether the context matters. A form whose edit
// finds no text in the shipped stages comes back as an error (--check-forms runs this without a GL driver).
std::vector<std::pair<std::string, std::vector<gl::ShaderText>>> passthrough_forms(std::string& errors) {
  const gl::ProgramSource source =
      gl::shadow_program_source(nv_program_config(Technique::nv_swizzle, Storage::linear_depth, false), 8);
  const std::vector<gl::ShaderText> shipped = gl::program_texts(source.stages, source.defines);
  const StageEdit invocations{GL_GEOMETRY_SHADER,
                              swap("layout(triangles) in;", "layout(invocations = 1, triangles) in;")};
  const StageEdit anonymous{GL_GEOMETRY_SHADER, swap("vec4 gl_Position; } gl_in[];", "vec4 gl_Position; };")};
  const StageEdit whole_block{
      GL_GEOMETRY_SHADER,
      swap("{ vec4 gl_Position; }", "{ vec4 gl_Position; float gl_PointSize; float gl_ClipDistance[]; }")};
  const StageEdit absolute_layer{GL_GEOMETRY_SHADER, swap("layout(viewport_relative) out int gl_Layer;", "")};
  const StageEdit version_460{GL_GEOMETRY_SHADER, swap("#version 450", "#version 460 core")};
  // world_position in a block through all three stages (the spec's own examples pass blocks).
  const std::vector<StageEdit> blocks = {
      {GL_VERTEX_SHADER, swap("layout(location = 0) out vec3 world_position;",
                              "layout(location = 0) out ShadowVertex { vec3 world_position; };")},
      {GL_GEOMETRY_SHADER,
       swap("layout(passthrough, location = 0) in vec3 world_position[];",
            "layout(passthrough, location = 0) in ShadowVertex { vec3 world_position; } v_in[];")},
      {GL_FRAGMENT_SHADER, swap("layout(location = 0) in vec3 world_position;",
                                "layout(location = 0) in ShadowVertex { vec3 world_position; };")}};
  const std::vector<std::pair<std::string, std::vector<StageEdit>>> forms = {
      {"shipped", {}},
      {"invocations = 1 declared", {invocations}},
      {"gl_PerVertex redeclared without the gl_in instance name", {anonymous}},
      {"gl_PerVertex with gl_PointSize and gl_ClipDistance[]", {whole_block}},
      {"all three (an emulator's GLSL that runs on NVIDIA GL)", {invocations, anonymous, whole_block}},
      {"gl_Layer not redeclared viewport_relative", {absolute_layer}},
      {"#version 460 core", {version_460}},
      {"world_position in a passthrough block", blocks},
  };
  std::vector<std::pair<std::string, std::vector<gl::ShaderText>>> out;
  for (const auto& [name, edits] : forms) {
    std::vector<gl::ShaderText> stages = shipped;
    try {
      for (gl::ShaderText& s : stages)
        for (const StageEdit& e : edits)
          if (s.type == e.stage) s.text = e.edit(s.text);
      out.emplace_back(name, std::move(stages));
    } catch (const std::exception& e) {
      errors += "passthrough form '" + name + "': " + e.what() + "\n";
    }
  }
  return out;
}

void probe_passthrough_forms(const char* profile) {
  std::string errors;
  for (const auto& [name, stages] : passthrough_forms(errors)) {
    print_compile_logs(std::string(profile) + " " + name, stages);
    try_link(std::string(profile) + " passthrough form: " + name, stages);
  }
  if (!errors.empty()) std::printf("FAILED: %s", errors.c_str());
}

// Self-contained passthrough programs, none of this project's text: whether this context links the
// extension's own example at all (what the GL backend asks to choose its context), then each feature the
// shipped stage adds.
void probe_minimal_programs(const char* profile) {
  const std::vector<gl::ShaderText> example = gl::passthrough_example();
  std::vector<gl::ShaderText> mask = example;  // NV_viewport_array2's viewport mask and relative layer
  for (gl::ShaderText& s : mask)
    if (s.type == GL_GEOMETRY_SHADER)
      s.text = swap("void main() { gl_Layer = 0; }",
                    "layout(viewport_relative) out int gl_Layer;\n"
                    "void main() { gl_ViewportMask[0] = 0x3F; gl_Layer = 0; }")(
          swap("layout(triangles) in;",
               "#extension GL_NV_viewport_array2 : require\nlayout(triangles) in;")(s.text));
  const std::string v = "#version 450\n";
  const std::vector<gl::ShaderText> loose = {
      {GL_VERTEX_SHADER, "loose.vert",
       v + "layout(location = 0) in vec3 p;\nlayout(location = 0) out vec3 q;\n"
           "void main() { q = p; gl_Position = vec4(p, 1.0); }\n"},
      {GL_GEOMETRY_SHADER, "loose.geom",
       v + "#extension GL_NV_geometry_shader_passthrough : require\nlayout(triangles) in;\n"
           "layout(passthrough) in gl_PerVertex { vec4 gl_Position; } gl_in[];\n"
           "layout(passthrough, location = 0) in vec3 q[];\nvoid main() { gl_Layer = 0; }\n"},
      {GL_FRAGMENT_SHADER, "loose.frag",
       v + "layout(location = 0) in vec3 q;\nlayout(location = 0) out vec4 c;\nvoid main() { c = vec4(q, "
           "1.0); }\n"}};
  const std::vector<std::pair<std::string, std::vector<gl::ShaderText>>> programs = {
      {"the extension's example (blocks, gl_Layer)", example},
      {"the example with NV_viewport_array2's mask and viewport_relative layer", mask},
      {"a loose located passthrough variable", loose},
  };
  for (const auto& [name, stages] : programs) {
    print_compile_logs(std::string(profile) + " minimal", stages);
    try_link(std::string(profile) + " minimal: " + name, stages);
  }
}

// In one context: every shipped program linked, then the passthrough forms and the minimal programs.
struct ProbeResult {
  bool missing_extensions = false;
  bool shipped_linked = true;   // every shipped nv_swizzle and mesh_shader program
  bool example_linked = false;  // the extension's example: what the GL backend's --gl-profile auto asks
};

ProbeResult probe(gl::GlProfile profile) {
  gl::EglContext context("surfaceless", 0, false, profile);
  const char* name = profile == gl::GlProfile::core ? "core" : "compatibility";
  std::printf("GL %s | %s | %s profile\n", reinterpret_cast<const char*>(glGetString(GL_VERSION)),
              reinterpret_cast<const char*>(glGetString(GL_RENDERER)), name);
  ProbeResult r;
  std::string missing;
  for (const char* ext : {"GL_NV_viewport_swizzle", "GL_NV_viewport_array2",
                          "GL_NV_geometry_shader_passthrough", "GL_NV_mesh_shader"})
    if (!epoxy_has_gl_extension(ext)) missing += std::string(missing.empty() ? "" : ", ") + ext;
  if (!missing.empty()) {
    std::printf("SKIP: %s missing on this driver: nothing to link\n", missing.c_str());
    r.missing_extensions = true;
    return r;
  }
  for (const CaseConfig& c : nv_program_configs()) {
    const gl::ProgramSource source = gl::shadow_program_source(c, 8);
    r.shipped_linked &= try_link(std::string(name) + " " + nv_program_name(c),
                                 gl::program_texts(source.stages, source.defines));
  }
  r.example_linked = gl::passthrough_link_error().empty();
  probe_passthrough_forms(name);
  probe_minimal_programs(name);
  return r;
}

}  // namespace

// Exit 0 when every shipped program links in the context the GL backend's --gl-profile auto takes: core, or
// compatibility where only that links the extension's example (gl_passthrough.h).
int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--check-forms") {  // no GL: every form's edits find their text
    std::string errors;
    const size_t count = passthrough_forms(errors).size();
    std::printf("%zu passthrough forms built%s%s", count, errors.empty() ? "\n" : "; ", errors.c_str());
    return errors.empty() ? 0 : 1;
  }
  try {
    const ProbeResult core = probe(gl::GlProfile::core);
    if (core.missing_extensions) return 77;
    ProbeResult compatibility;
    try {
      compatibility = probe(gl::GlProfile::compatibility);
    } catch (const std::exception& e) {
      std::printf("compatibility profile: %s\n", e.what());
      compatibility.shipped_linked = compatibility.example_linked = false;
    }
    const bool auto_takes_compatibility = !core.example_linked && compatibility.example_linked;
    const bool linked = auto_takes_compatibility ? compatibility.shipped_linked : core.shipped_linked;
    std::printf("--gl-profile auto takes a %s context: %s\n",
                auto_takes_compatibility ? "compatibility" : "core",
                linked ? "every shipped program linked there" : "a shipped program did not link there");
    return linked ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("FAILED: %s\n", e.what());
    return 1;
  }
}
