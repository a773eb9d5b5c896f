#pragma once
// SPIR-V of the shared GLSL in shaders/, compiled by glslc at build time (CMakeLists.txt lists the variants).
// Keys: "<file>:<DEFINE>,<DEFINE>" with defines in the order CMakeLists.txt gives them.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace omnishadow::vk {

const std::map<std::string, std::vector<uint32_t>>& embedded_spirv();

}  // namespace omnishadow::vk
