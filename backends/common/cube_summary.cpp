#include "backends/common/cube_summary.h"

#include <cmath>
#include <cstring>

namespace omnishadow::cube {

uint32_t summary_mix_low(uint32_t v, uint32_t i) {
  uint32_t x = v ^ (i * 0x9E3779B9u);
  x ^= x >> 16, x *= 0x85EBCA6Bu, x ^= x >> 13, x *= 0xC2B2AE35u, x ^= x >> 16;
  return x;
}

uint32_t summary_mix_high(uint32_t v, uint32_t i) {
  uint32_t x = v + (i * 0x632BE5ABu) + 0x5BD1E995u;
  x ^= x >> 15, x *= 0x2C1B3C6Du, x ^= x >> 12, x *= 0x297A2D39u, x ^= x >> 15;
  return x;
}

void unpack_summary(const void* buffer, int cube_size, Images& img) {
  uint32_t words[kSummaryWords];
  std::memcpy(words, buffer, sizeof words);
  const int stride = cube_sample_stride(cube_size);
  const size_t grid = size_t(cube_size / stride), per_face = grid * grid;
  const auto* values = static_cast<const float*>(buffer) + kSummaryWords;
  img.cube_sample_stride = stride;
  img.cube_summary_on_device = true;
  for (size_t f = 0; f < 6; ++f) {
    img.cube_summary[f].hash = uint64_t(words[6 + f]) << 32 | words[f];
    img.cube_summary[f].non_finite = words[12 + f];
    img.cube_sample[f].assign(values + f * per_face, values + (f + 1) * per_face);
  }
}

void sample_to_distance(Images& img, Storage storage, float near_plane, float far_plane, DepthRange range) {
  const int stride = img.cube_sample_stride, grid = img.cube_size / stride;
  for (auto& face : img.cube_sample)
    for (int y = 0; y < grid; ++y)
      for (int x = 0; x < grid; ++x) {
        float& v = face[size_t(y) * size_t(grid) + size_t(x)];
        v = stored_to_distance(storage, v, x * stride + stride / 2, y * stride + stride / 2, img.cube_size,
                               near_plane, far_plane, range);
      }
}

void summarize_on_host(Images& img) {
  const int n = img.cube_size, stride = cube_sample_stride(n), grid = n / stride;
  img.cube_sample_stride = stride;
  img.cube_summary_on_device = false;
  for (size_t f = 0; f < 6; ++f) {
    const std::vector<float>& face = img.cube_distance[f];
    img.cube_sample[f].clear();
    if (face.empty()) continue;  // a layout of fewer layers (dual_paraboloid: 2) leaves the rest empty
    uint32_t low = 0, high = 0;
    uint64_t non_finite = 0;
    for (size_t i = 0; i < face.size(); ++i) {
      uint32_t bits;
      std::memcpy(&bits, &face[i], 4);
      low += summary_mix_low(bits, uint32_t(i));
      high += summary_mix_high(bits, uint32_t(i));
      non_finite += !std::isfinite(face[i]);
    }
    img.cube_summary[f] = {uint64_t(high) << 32 | low, non_finite};
    for (int y = 0; y < grid; ++y)
      for (int x = 0; x < grid; ++x)
        img.cube_sample[f].push_back(
            face[size_t(y * stride + stride / 2) * size_t(n) + size_t(x * stride + stride / 2)]);
  }
}

}  // namespace omnishadow::cube
