#include "backends/common/shader_variants.h"

namespace omnishadow::gpu {

std::vector<std::string> shadow_vertex_defines(const CaseConfig& c) {
  const bool cull = c.optimizations.face_culling;
  switch (c.technique) {
    case Technique::six_pass: return {"TECHNIQUE_SIX_PASS"};
    case Technique::geometry_shader:
    case Technique::geometry_shader_instanced: return {"TECHNIQUE_GEOMETRY_SHADER"};
    case Technique::vs_layer:
      return cull ? std::vector<std::string>{"TECHNIQUE_VS_LAYER", "FACE_CULLING"}
                  : std::vector<std::string>{"TECHNIQUE_VS_LAYER"};
    case Technique::multiview: return {"TECHNIQUE_MULTIVIEW"};
  }
  return {"TECHNIQUE_SIX_PASS"};
}

std::vector<std::string> shadow_geometry_defines(const CaseConfig& c) {
  if (c.technique != Technique::geometry_shader && c.technique != Technique::geometry_shader_instanced) return {};
  std::vector<std::string> d{"TECHNIQUE_GEOMETRY_SHADER"};
  if (c.technique == Technique::geometry_shader_instanced) d.push_back("GS_INSTANCED");
  if (c.optimizations.face_culling) d.push_back("FACE_CULLING");
  return d;
}

std::string variant_key(const std::string& file, const std::vector<std::string>& defines) {
  std::string key = file + ":";
  for (size_t i = 0; i < defines.size(); ++i) key += (i ? "," : "") + defines[i];
  return key;
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

std::vector<std::string> lighting_defines(const CaseConfig& c) {
  std::vector<std::string> d{storage_define(c.storage), filter_define(c.filter)};
  if (c.remedies.bias == BiasMode::zero) d.push_back("BIAS_ZERO");
  if (c.remedies.bias == BiasMode::slope) d.push_back("BIAS_SLOPE");
  if (c.remedies.normal_offset) d.push_back("NORMAL_OFFSET");
  return d;
}

}  // namespace omnishadow::gpu
