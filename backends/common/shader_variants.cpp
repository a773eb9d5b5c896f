#include "backends/common/shader_variants.h"

namespace omnishadow::gpu {

std::vector<std::string> technique_defines(Technique t) {
  switch (t) {
    case Technique::six_pass: return {"TECHNIQUE_SIX_PASS"};
    case Technique::geometry_shader: return {"TECHNIQUE_GEOMETRY_SHADER"};
    case Technique::geometry_shader_instanced: return {"TECHNIQUE_GEOMETRY_SHADER", "GS_INSTANCED"};
    case Technique::vs_layer: return {"TECHNIQUE_VS_LAYER"};
    case Technique::multiview: return {"TECHNIQUE_MULTIVIEW"};
  }
  return {"TECHNIQUE_SIX_PASS"};
}

std::string storage_define(Storage s) {
  return s == Storage::r32f_distance ? "STORAGE_R32F_DISTANCE" : "STORAGE_LINEAR_DEPTH";
}

std::string filter_define(Filter f) {
  switch (f) {
    case Filter::hard: return "FILTER_HARD";
    case Filter::pcf_grid64: return "FILTER_PCF_GRID64";
    case Filter::pcf_disk20: return "FILTER_PCF_DISK20";
    case Filter::hw_compare2x2: return "FILTER_HW_COMPARE2X2";
  }
  return "FILTER_HARD";
}

}  // namespace omnishadow::gpu
