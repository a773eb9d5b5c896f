#pragma once
// The cube summary's arithmetic on the host: the hash mixes of shaders/cube_summary.comp (change both
// together), the buffer it writes, and the same summary computed from a cube already in host memory (backends
// that have no device, such as test doubles, and the checks' own tests).

#include <cstdint>
#include <vector>

#include "backends/backend.h"
#include "backends/common/cube_faces.h"

namespace omnishadow::cube {

uint32_t summary_mix_low(uint32_t value_bits, uint32_t texel_index);
uint32_t summary_mix_high(uint32_t value_bits, uint32_t texel_index);

// The shader's buffer: 24 words (hash halves and non-finite counts per face), then the check grid's values.
inline constexpr size_t kSummaryWords = 24;
inline size_t summary_buffer_bytes(int cube_size) {
  const size_t grid = size_t(cube_size / cube_sample_stride(cube_size));
  return kSummaryWords * 4 + 6 * grid * grid * 4;
}
// Fills img.cube_summary and (as stored values) img.cube_sample from the shader's buffer.
void unpack_summary(const void* buffer, int cube_size, Images& img);
// The check grid's stored values to light distances (stored_to_distance at each grid texel).
void sample_to_distance(Images& img, Storage storage, float near_plane, float far_plane, DepthRange range);
// The summary and sample of img.cube_distance, hashing the distances: for a cube that is only in host memory.
void summarize_on_host(Images& img);

}  // namespace omnishadow::cube
