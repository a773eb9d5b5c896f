#include "bench/truth/image_compare.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace omnishadow::bench {
namespace {

template <typename T>
Difference compare(const std::vector<T>& a, const std::vector<T>& b, double tolerance) {
  if (a.size() != b.size()) throw std::invalid_argument("compared images differ in size");
  Difference d;
  d.total = a.size();
  for (size_t i = 0; i < a.size(); ++i) {
    double x = static_cast<double>(a[i]), y = static_cast<double>(b[i]);
    if (x == y) continue;  // also equal infinities / FLT_MAX clears
    double diff = std::fabs(x - y);
    if (std::isnan(diff)) diff = std::numeric_limits<double>::infinity();
    d.max_abs = std::max(d.max_abs, diff);
    if (diff > tolerance) ++d.differing;
  }
  return d;
}

}  // namespace

Difference compare_values(const std::vector<float>& a, const std::vector<float>& b, double tolerance) {
  return compare(a, b, tolerance);
}

Difference compare_values(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, double tolerance) {
  return compare(a, b, tolerance);
}

std::vector<uint8_t> diff_image_rgb(const std::vector<float>& a, const std::vector<float>& b,
                                    const std::vector<float>& reference_grey, int width, int height,
                                    double tolerance, double scale, bool flip) {
  std::vector<uint8_t> rgb(static_cast<size_t>(width) * static_cast<size_t>(height) * 3);
  for (int y = 0; y < height; ++y) {
    int src_row = flip ? height - 1 - y : y;
    for (int x = 0; x < width; ++x) {
      size_t i = static_cast<size_t>(src_row) * static_cast<size_t>(width) + static_cast<size_t>(x);
      size_t o = (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 3;
      double diff = a[i] == b[i] ? 0.0 : std::fabs(static_cast<double>(a[i]) - static_cast<double>(b[i]));
      if (std::isnan(diff)) diff = std::numeric_limits<double>::infinity();
      if (diff > tolerance) {
        double t = std::clamp(scale > 0 ? diff / scale : 1.0, 0.25, 1.0);
        rgb[o] = static_cast<uint8_t>(255.0 * t);
        rgb[o + 1] = rgb[o + 2] = 0;
      } else {
        auto g = static_cast<uint8_t>(std::clamp(reference_grey[i], 0.0f, 1.0f) * 127.0f);
        rgb[o] = rgb[o + 1] = rgb[o + 2] = g;
      }
    }
  }
  return rgb;
}

}  // namespace omnishadow::bench
