#include "backends/gl/gl_passthrough.h"

#include <stdexcept>

namespace omnishadow::gl {

std::vector<ShaderText> passthrough_example() {
  const std::string v = "#version 450\n";
  return {{GL_VERTEX_SHADER, "passthrough_example.vert",
           v + "layout(location = 0) in vec3 p;\nout Inputs { vec3 q; } v_out;\n"
               "void main() { v_out.q = p; gl_Position = vec4(p, 1.0); }\n"},
          {GL_GEOMETRY_SHADER, "passthrough_example.geom",
           v + "#extension GL_NV_geometry_shader_passthrough : require\nlayout(triangles) in;\n"
               "layout(passthrough) in gl_PerVertex { vec4 gl_Position; } gl_in[];\n"
               "layout(passthrough) in Inputs { vec3 q; } v_in[];\nvoid main() { gl_Layer = 0; }\n"},
          {GL_FRAGMENT_SHADER, "passthrough_example.frag",
           v + "in Inputs { vec3 q; } f_in;\nlayout(location = 0) out vec4 c;\n"
               "void main() { c = vec4(f_in.q, 1.0); }\n"}};
}

std::string passthrough_link_error() {
  try {
    glDeleteProgram(link_program(passthrough_example()));
    return "";
  } catch (const std::runtime_error& e) {
    return e.what();  // link_program's messages are one line (the driver's log joined)
  }
}

}  // namespace omnishadow::gl
