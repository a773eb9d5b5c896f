#pragma once
// Whether the current GL context links a passthrough geometry shader (NV_geometry_shader_passthrough), the
// stage nv_swizzle needs. NVIDIA's driver (580, H100) links one only in a compatibility-profile context: in a
// core context it refuses even the extension's own example with "max_vertices layout qualifier must be
// declared in at least one of the GLSL geometry shaders" (a qualifier the extension forbids there), while
// every form links in a compatibility context (tests/gl_nv_link_probe.cpp printed both). The GL backend links
// the example once to choose its context (--gl-profile auto).
#include <string>
#include <vector>

#include "backends/gl/gl_program.h"

namespace omnishadow::gl {

// The extension's example, self-contained: a vertex stage writing a block, the passthrough stage forwarding
// it and gl_Position and writing gl_Layer, a fragment stage reading the block.
std::vector<ShaderText> passthrough_example();

// "" when the current context links passthrough_example(); else the driver's message, one line.
std::string passthrough_link_error();

}  // namespace omnishadow::gl
