#pragma once
// Out-of-memory as a result, not a crash: before a case allocates, its targets and the harness's read-back
// copies are estimated and compared with what the process can get (MemAvailable, the cgroup's memory.max,
// RLIMIT_AS, and the device heap where the backend knows it). A case that cannot fit fails with both figures
// in its reason; allocations that fail anyway (GL_OUT_OF_MEMORY, VK_ERROR_OUT_OF_*_MEMORY, std::bad_alloc)
// are caught per case.

#include <cstdint>
#include <string>

#include "backends/backend.h"

namespace omnishadow::bench {

struct MemoryNeed {
  uint64_t device_bytes = 0;  // cube (stored + depth) and lighting targets, on the device
  uint64_t host_bytes = 0;    // read-back copies the harness holds at once (images, reference, accuracy)
};
// The point lights' shadow storage on the device: the depth cube, the colour cube beside it (r32f distances,
// moments) and the blur's intermediate for a moments filter, for each of the case's lights. The memory column
// of the filter table. Texels of the stored image: the layout's layers x size^2 per light (the equal-memory
// axis of layouts), times the light count; for layout atlas, the atlas's width x height (borders and packing
// included), its tiles sized from `scene` where given (--atlas-tiles by_distance), else every light at --cube
// (an upper bound).
uint64_t shadow_texels(const CaseConfig& config, const scene::Scene* scene = nullptr);
uint64_t shadow_storage_bytes(const CaseConfig& config, const scene::Scene* scene = nullptr);
// Bytes a texel of the case's shadow storage takes: depth, and colour (twice with the moments blur).
uint64_t shadow_bytes_per_texel(const CaseConfig& config);
MemoryNeed estimate_case_memory(const CaseConfig& config, CubeReadBack cube = CubeReadBack::full);

struct MemoryAvailable {
  uint64_t host_bytes = 0;  // min(MemAvailable, cgroup memory.max - memory.current, RLIMIT_AS - VmSize)
  std::string host_limit;   // which of those applied, for the reason
  // --memory-budget: the device is planned as if it had this many bytes (0: as it reports). On a driver that
  // keeps its targets in host memory the budget caps the host figure instead.
  uint64_t device_budget = 0;
};
MemoryAvailable host_memory_available();

// "" when the case fits; otherwise the reason: "out of memory (predicted): needs 9.4 GiB ..., 2.1 GiB
// available (RLIMIT_AS)". Device memory that is host memory (CPU drivers) counts against the host figure.
std::string memory_shortfall(const MemoryNeed& need, const MemoryAvailable& host, const DeviceInfo& device);
// The same once the budget is applied: device memory `device_bytes` (0 = unknown), named by `device_source`.
std::string shortfall_against(const MemoryNeed& need, const MemoryAvailable& host, bool shares_host_memory,
                              uint64_t device_bytes, const std::string& device_source);

std::string format_bytes(uint64_t bytes);

}  // namespace omnishadow::bench
