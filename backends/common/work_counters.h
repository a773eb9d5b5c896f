#pragma once
// Per-pass work counters and the one table that names them: the JSON key (also the Google Benchmark counter
// suffix, "shadow_<name>"), the member, the GL_ARB_pipeline_statistics_query target and the Vulkan statistic
// bit. Both backends and every writer iterate this table; adding a statistic is one row here.

#include <array>
#include <cstdint>

namespace omnishadow {

// Deterministic for a given case and frame, so any change is a change of work, not noise. `valid` is false
// where the API or driver cannot count (draw_calls is counted by the backend itself and always valid).
struct PassCounters {
  bool valid = false;
  uint64_t vertices_submitted = 0;
  uint64_t primitives_submitted = 0;
  uint64_t vs_invocations = 0;
  uint64_t gs_invocations = 0;
  uint64_t gs_primitives = 0;
  uint64_t clipping_input = 0;
  uint64_t clipping_output = 0;
  uint64_t fs_invocations = 0;  // llvmpipe counts in 4x4 blocks, not per fragment
  uint64_t draw_calls = 0;      // counted by the backend itself
};

struct PipelineStatistic {
  const char* name;  // JSON key, and the Google Benchmark counter after "<pass>_"
  uint64_t PassCounters::*member;
  uint32_t gl_target;  // GL_ARB_pipeline_statistics_query / GL 4.6 query target
  uint32_t vk_bit;     // VkQueryPipelineStatisticFlagBits
};

// In increasing Vulkan bit order, which is the order vkGetQueryPoolResults returns them in. The GL and Vulkan
// values are checked against the APIs' own headers where each backend is compiled (static_asserts).
inline constexpr std::array<PipelineStatistic, 8> kPipelineStatistics = {{
    {"vertices_submitted", &PassCounters::vertices_submitted, 0x82EE /* GL_VERTICES_SUBMITTED_ARB */, 0x01},
    {"primitives_submitted", &PassCounters::primitives_submitted, 0x82EF /* GL_PRIMITIVES_SUBMITTED_ARB */,
     0x02},
    {"vs_invocations", &PassCounters::vs_invocations, 0x82F0 /* GL_VERTEX_SHADER_INVOCATIONS_ARB */, 0x04},
    {"gs_invocations", &PassCounters::gs_invocations, 0x887F /* GL_GEOMETRY_SHADER_INVOCATIONS */, 0x08},
    {"gs_primitives", &PassCounters::gs_primitives, 0x82F3 /* GL_GEOMETRY_SHADER_PRIMITIVES_EMITTED_ARB */,
     0x10},
    {"clipping_input", &PassCounters::clipping_input, 0x82F6 /* GL_CLIPPING_INPUT_PRIMITIVES_ARB */, 0x20},
    {"clipping_output", &PassCounters::clipping_output, 0x82F7 /* GL_CLIPPING_OUTPUT_PRIMITIVES_ARB */, 0x40},
    {"fs_invocations", &PassCounters::fs_invocations, 0x82F4 /* GL_FRAGMENT_SHADER_INVOCATIONS_ARB */, 0x80},
}};

constexpr bool statistics_in_vulkan_bit_order() {
  for (size_t i = 1; i < kPipelineStatistics.size(); ++i)
    if (kPipelineStatistics[i].vk_bit <= kPipelineStatistics[i - 1].vk_bit) return false;
  return true;
}
static_assert(statistics_in_vulkan_bit_order(), "vkGetQueryPoolResults returns statistics in bit order");

}  // namespace omnishadow
