#include "bench/truth/moments_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "backends/common/cube_faces.h"
#include "backends/common/storage_filter_tables.h"

namespace omnishadow::bench {
namespace {

constexpr double kFloatUnit = 0x1p-24;  // unit roundoff of binary32
// The GLSL and SPIR-V environments let a device flush binary32 subnormals to zero in and out of every
// operation (a warp's e^(-2cz) near the format's limit is one): up to 2^-126 absolute each time.
constexpr double kFloatTiny = 0x1p-126;
// binary16 conversions may round to nearest or toward zero (the APIs leave it to the implementation): up to
// one ulp, 2^-10 of the value.
constexpr double kHalfUnit = 0x1p-10;
constexpr double kHalfTiny = 0x1p-24;  // binary16's subnormal step: its rounding's absolute floor
constexpr int kBlurWeights[5] = {1, 4, 6, 4, 1};

struct Interval {
  double low, high;
};
// One cube of intervals, `channels` per texel, faces in order.
using IntervalCube = std::array<std::vector<Interval>, 6>;

double depth_step(DepthFormat f) {
  return f == DepthFormat::d16 ? 1.0 / 65535.0 : f == DepthFormat::d24 ? 1.0 / 16777215.0 : 0.0;
}

// The storage's moment `channel` of z (the C++ form of shaders/moments.glsl's distance_moments); `c` is the
// moments' parameter where they have an exponent (esm, evsm), `scale` vsm's distance scale (1, or far in
// world units).
double moment(MomentKind kind, int channel, double z, double c, double scale) {
  switch (kind) {
    case MomentKind::vsm:
      return channel == 0 ? z * scale : (z * scale) * (z * scale);
    case MomentKind::esm:
      return std::exp(c * std::min(z, 1.0));
    case MomentKind::evsm: {
      const double p = std::exp(c * std::min(z, 1.0)), n = std::exp(-c * std::min(z, 1.0));
      return channel == 0 ? p : channel == 1 ? p * p : channel == 2 ? -n : n * n;
    }
    case MomentKind::msm: {
      const double m = std::min(z, 1.0);
      return channel == 0 ? m : channel == 1 ? m * m : channel == 2 ? m * m * m : m * m * m * m;
    }
    case MomentKind::none:
      break;
  }
  return 0.0;
}

// How far the device's float evaluation of that moment may be from it, relative: vsm's z^2 one correctly
// rounded multiply (and with a scale, its product's rounding once in d and twice more in d^2); esm's exp(c z)
// the product's rounding (|x| 2^-24 of exp's argument x = c z) and exp's own (3 + 2|x|) ulps (the GLSL and
// Vulkan precision tables), an ulp being at most 2^-23 of the value.
double moment_rounding(MomentKind kind, int channel, double z, double c, double scale) {
  switch (kind) {
    case MomentKind::vsm:
      return (channel == 0 ? 0.0 : kFloatUnit) + (scale != 1.0 ? (channel == 0 ? 1 : 3) * kFloatUnit : 0.0);
    case MomentKind::esm: {
      const double x = std::abs(c * std::min(z, 1.0));
      return x * kFloatUnit + (3.0 + 2.0 * x) * 0x1p-23;
    }
    case MomentKind::evsm: {  // squares: twice the exponential's error and the multiply's rounding
      const double x = std::abs(c * std::min(z, 1.0)), exp_error = x * kFloatUnit + (3.0 + 2.0 * x) * 0x1p-23;
      return channel % 2 == 0 ? exp_error : 2.0 * exp_error + 2.0 * kFloatUnit;
    }
    case MomentKind::msm:
      return 2.0 * channel * kFloatUnit;  // z^2: one multiply; z^3 and z^4: two (doubled: generous)
    case MomentKind::none:
      break;
  }
  return 0.0;
}

// Rounding to the moments' format: for float only a subnormal's flush (the shader's value is already float),
// else binary16's rounding.
Interval stored(Interval v, bool half) {
  if (!half) return {v.low - kFloatTiny, v.high + kFloatTiny};
  return {v.low - std::abs(v.low) * kHalfUnit - kHalfTiny, v.high + std::abs(v.high) * kHalfUnit + kHalfTiny};
}

IntervalCube unblurred(const Images& img, MomentKind kind, int channels, DepthFormat depth_format, bool half,
                       double c, double scale) {
  IntervalCube out;
  const double far_plane = img.light_far, step = depth_step(depth_format);
  for (int f = 0; f < 6; ++f) {
    const std::vector<float>& distance = img.cube_distance[static_cast<size_t>(f)];
    out[static_cast<size_t>(f)].resize(distance.size() * size_t(channels));
    // A face view culling left out holds moments an earlier frame left (blurred again since): unknown, and so
    // is every blurred texel whose taps reach it.
    if (!img.face_drawn(f)) {
      std::fill(out[size_t(f)].begin(), out[size_t(f)].end(), Interval{-INFINITY, INFINITY});
      continue;
    }
    for (size_t i = 0; i < distance.size(); ++i) {
      const double z = double(distance[i]) / far_plane;
      double low = z * (1.0 - 0x1p-23) - step, high = z * (1.0 + 0x1p-23) + step;
      if (z >= 1.0 - step - 0x1p-23) high = std::sqrt(3.0) * (1.0 + 0x1p-23);  // clamped depth: any z beyond
      low = std::max(low, 0.0);
      for (int ch = 0; ch < channels; ++ch) {
        Interval m{moment(kind, ch, low, c, scale), moment(kind, ch, high, c, scale)};
        if (m.low > m.high) std::swap(m.low, m.high);
        const double rounding =
            std::max(moment_rounding(kind, ch, low, c, scale), moment_rounding(kind, ch, high, c, scale));
        m = {m.low - std::abs(m.low) * rounding - kFloatTiny,
             m.high + std::abs(m.high) * rounding + kFloatTiny};
        out[static_cast<size_t>(f)][i * size_t(channels) + size_t(ch)] = stored(m, half);
      }
    }
  }
  return out;
}

// One pass of shaders/moments_blur.comp over intervals, along `axis`.
IntervalCube blur(const IntervalCube& in, int size, int channels, int axis, bool half) {
  constexpr double kGamma5 = 5.0 * kFloatUnit / (1.0 - 5.0 * kFloatUnit);
  IntervalCube out;
  for (int f = 0; f < 6; ++f) {
    out[static_cast<size_t>(f)].resize(in[static_cast<size_t>(f)].size());
    for (int t = 0; t < size; ++t)
      for (int s = 0; s < size; ++s)
        for (int c = 0; c < channels; ++c) {
          double low = 0.0, high = 0.0, magnitude = 0.0;
          for (int k = -2; k <= 2; ++k) {
            const cube::FaceTexel n = cube::neighbour_texel(f, s, t, axis, k, size);
            const Interval& v = in[static_cast<size_t>(n.face)]
                                  [(size_t(n.t) * size_t(size) + size_t(n.s)) * size_t(channels) + size_t(c)];
            low += kBlurWeights[k + 2] * v.low;
            high += kBlurWeights[k + 2] * v.high;
            magnitude += kBlurWeights[k + 2] * std::max(std::abs(v.low), std::abs(v.high));
          }
          const double rounding = kGamma5 * magnitude / 16.0 + 5.0 * kFloatTiny;  // five products may flush
          out[static_cast<size_t>(f)][(size_t(t) * size_t(size) + size_t(s)) * size_t(channels) + size_t(c)] =
              stored({low / 16.0 - rounding, high / 16.0 + rounding}, half);
        }
  }
  return out;
}

}  // namespace

MomentsReport check_moments(const Images& img, Storage storage, DepthFormat depth_format,
                            const MomentsTuning& tuning) {
  MomentsReport r;
  const StorageTraits& row = traits(storage);
  const int channels = row.colour_channels, size = img.cube_size;
  if (row.moments == MomentKind::none || !img.has_full_cube() || img.moments[0].empty() ||
      img.moment_channels != channels)
    return r;
  const ColourFormat format = colour_format(storage, depth_format);
  const bool half = is_half(format);
  IntervalCube bound = unblurred(img, row.moments, channels, depth_format, half,
                                 double(moments_parameter(storage, format, tuning)),
                                 double(moments_distance_scale(tuning, float(img.light_far))));
  bound = blur(bound, size, channels, 0, half);
  bound = blur(bound, size, channels, 1, half);
  double worst = -1.0;
  for (int f = 0; f < 6; ++f) {
    if (!img.face_drawn(f)) continue;  // not drawn this frame (view culling)
    const std::vector<float>& got = img.moments[static_cast<size_t>(f)];
    for (size_t i = 0; i < got.size(); ++i) {
      ++r.values;
      const double v = got[i];
      if (!std::isfinite(v)) {
        ++r.non_finite;
        continue;
      }
      const Interval& b = bound[static_cast<size_t>(f)][i];
      const double beyond = std::max(b.low - v, v - b.high);
      if (beyond <= 0.0) continue;
      ++r.outside;
      if (beyond > worst) {
        worst = beyond;
        const size_t texel = i / size_t(channels);
        r.face = f, r.s = int(texel % size_t(size)), r.t = int(texel / size_t(size)),
        r.channel = int(i % size_t(channels));
        r.got = v, r.low = b.low, r.high = b.high;
      }
    }
  }
  return r;
}

std::string describe(const MomentsReport& r) {
  char buf[320];
  if (r.outside == 0)
    std::snprintf(buf, sizeof buf, "%llu of %llu stored moments are not finite",
                  (unsigned long long)r.non_finite, (unsigned long long)r.values);
  else
    std::snprintf(
        buf, sizeof buf,
        "%llu of %llu stored moments outside the blur of the stored depths' moments (%llu not finite); "
        "worst face %d texel (%d, %d) moment %d: %.9g not in [%.9g, %.9g]",
        (unsigned long long)r.outside, (unsigned long long)r.values, (unsigned long long)r.non_finite, r.face,
        r.s, r.t, r.channel + 1, r.got, r.low, r.high);
  return buf;
}

}  // namespace omnishadow::bench
