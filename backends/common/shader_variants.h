#pragma once
// The macros that select a variant of the shared GLSL (shaders/), one table for both APIs: GL passes them to
// its compiler at run time, Vulkan looks up the SPIR-V that CMakeLists.txt compiled with the same names.

#include <string>
#include <vector>

#include "backends/common/case_config.h"

namespace omnishadow::gpu {

// The first define is the technique's own (the vertex-shader variant); GS_INSTANCED follows for the GS form.
std::vector<std::string> technique_defines(Technique t);
std::string storage_define(Storage s);
std::string filter_define(Filter f);

}  // namespace omnishadow::gpu
