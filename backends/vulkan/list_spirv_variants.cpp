// Build-time helper: writes every SPIR-V variant key the Vulkan backend can ask for
// (gpu::spirv_variant_keys), one per line, to the file named by argv[1]. cmake/embed_spirv.py compiles and
// embeds exactly these.
#include <exception>
#include <fstream>
#include <iostream>

#include "backends/common/shader_variants.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: list_spirv_variants OUTPUT\n";
    return 2;
  }
  try {
    std::ofstream out(argv[1]);
    for (const std::string& key : omnishadow::gpu::spirv_variant_keys()) out << key << "\n";
    return out ? 0 : 1;
  } catch (const std::exception& e) {
    // The variant tables check the conventions they are built from (face_swizzles: the projection's scales):
    // such a refusal stops the build with one line that scripts/experiments/mutants.py tells from a compile
    // error, not with std::terminate's abort.
    std::cerr << "omnishadow self-check failed: " << e.what() << "\n";
    return 1;
  }
}
