#pragma once
// SPIR-V of the shared GLSL in shaders/, compiled by glslc at build time (cmake/embed_spirv.py; the variants
// are listed by list_spirv_variants from the C++ tables). Keys: "<file>:<DEFINE>,<DEFINE>" with defines in
// the order list_spirv_variants gives them.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace omnishadow::vk {

const std::map<std::string, std::vector<uint32_t>>& embedded_spirv();
// sha256 of the embedded modules, back to back in the variant list's order (cmake/embed_spirv.py).
const char* embedded_spirv_pack_hash();
// How glslc optimised them (the build's OMNISHADOW_SPIRV_OPTIMIZATION), e.g. "performance (glslc -O)":
// results.json gives it as devices.vulkan.extra.spirv_optimization, since the driver's compiler sees a
// different program.
const char* embedded_spirv_optimization();

}  // namespace omnishadow::vk
