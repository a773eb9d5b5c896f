#pragma once
// Image agreement: how many values differ by more than a tolerance, and by how much at most.

#include <cstdint>
#include <string>
#include <vector>

namespace omnishadow::bench {

struct Difference {
  uint64_t total = 0;      // values compared
  uint64_t differing = 0;  // values whose absolute difference exceeds the tolerance
  double max_abs = 0.0;  // largest absolute difference (infinite if one side is not finite and the other is)
  double percent_differing() const { return total ? 100.0 * static_cast<double>(differing) / total : 0.0; }
};

// Elementwise over equal-sized buffers; two equal non-finite values (FLT_MAX clears, inf) count as equal.
Difference compare_values(const std::vector<float>& a, const std::vector<float>& b, double tolerance);
Difference compare_values(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, double tolerance);

// A visual diff: grey where equal (the reference, dimmed), red scaled by |a-b| / scale where they differ.
// `reference_grey` gives the grey level per value in [0,1]; returns top-down RGB rows if `flip` is set.
std::vector<uint8_t> diff_image_rgb(const std::vector<float>& a, const std::vector<float>& b,
                                    const std::vector<float>& reference_grey, int width, int height,
                                    double tolerance, double scale, bool flip);

}  // namespace omnishadow::bench
