#pragma once
// The macros that select a variant of the shared GLSL (shaders/), one table for both APIs: GL passes them to
// its compiler at run time, Vulkan looks up the SPIR-V that CMakeLists.txt compiled with the same names.

#include <string>
#include <vector>

#include "backends/common/case_config.h"

namespace omnishadow::gpu {

// Shadow pass: the vertex stage's defines (the technique's own; FACE_CULLING for vs_layer with culling) and the
// geometry stage's (TECHNIQUE_GEOMETRY_SHADER, GS_INSTANCED for the instanced form, FACE_CULLING); empty when
// the technique has no geometry stage. CMakeLists.txt compiles SPIR-V under exactly these lists.
std::vector<std::string> shadow_vertex_defines(const CaseConfig& c);
std::vector<std::string> shadow_geometry_defines(const CaseConfig& c);
// "shadow_depth.geom:TECHNIQUE_GEOMETRY_SHADER,FACE_CULLING": the key a variant is embedded under.
std::string variant_key(const std::string& file, const std::vector<std::string>& defines);
std::string storage_define(Storage s);
std::string filter_define(Filter f);
// The lighting fragment stage: storage, filter and, for the bias remedies, BIAS_ZERO / BIAS_SLOPE / NORMAL_OFFSET
// (CMakeLists.txt compiles one SPIR-V per combination).
std::vector<std::string> lighting_defines(const CaseConfig& c);

}  // namespace omnishadow::gpu
