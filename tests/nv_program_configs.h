#pragma once
// The GL shadow-pass programs of the techniques whose extensions Mesa lacks (nv_swizzle, mesh_shader): one
// case per technique, storage and culling setting that the common rules allow, each with a filter that reads
// its storage; and mesh_shader's every light in one pass, per storage. gl_shader_sources.cpp writes them for
// glslang; gl_nv_link_probe.cpp links them on the machine's driver.
#include <string>
#include <vector>

#include "backends/common/case_config.h"
#include "backends/common/case_support.h"
#include "backends/common/storage_filter_tables.h"

namespace omnishadow {

inline CaseConfig nv_program_config(Technique t, Storage s, bool cull) {
  CaseConfig c;
  c.technique = t;
  c.storage = s;
  for (Filter f : all_values<Filter>())  // a filter that reads this storage (its own, for the moments)
    if (traits(f).own_storage == s) c.filter = f;
  c.optimizations.face_culling = cull;
  return c;
}

inline std::vector<CaseConfig> nv_program_configs() {
  std::vector<CaseConfig> out;
  for (Technique t : {Technique::nv_swizzle, Technique::mesh_shader})
    for (Storage s : all_values<Storage>())
      for (bool cull : {false, true})
        if (CaseConfig c = nv_program_config(t, s, cull); common_support(c).ok) out.push_back(c);
  for (Storage s : all_values<Storage>()) {
    CaseConfig c = nv_program_config(Technique::mesh_shader, s, false);
    c.light_grouping = LightGrouping::all_lights;
    c.light_count = 4;
    if (common_support(c).ok) out.push_back(c);
  }
  return out;
}

// A name for the program: technique-storage[-cull].
inline std::string nv_program_name(const CaseConfig& c) {
  return std::string(to_string(c.technique)) + "-" + std::string(to_string(c.storage)) +
         (c.optimizations.face_culling ? "-cull" : "") +
         (c.light_grouping == LightGrouping::all_lights ? "-all_lights" : "");
}

}  // namespace omnishadow
