#pragma once
// The moments filters' stored moments against the depths the same shadow pass stored. The depth cube is
// checked against exact visibility by the cube truth (bench/truth/cube_truth.h); this check closes the chain:
// every blurred moment the lighting pass sampled must equal the blur of the moments of those depths, within
// what the APIs allow each step to round.
//
// Bounds, per texel and channel, as an interval carried through every step the device takes:
//   depth -> z:  z = distance / far read back as float (one rounding each way: 2^-23 relative), plus the
//   depth
//                format's step for d16 / d24 (the moments hold the unquantised z); a texel at depth 1 may
//                hold any z up to sqrt(3) (gl_FragDepth clamps, the moments do not: a face corner is sqrt(3)
//                x far away).
//   moments:     the storage's moment functions (monotone in z over [0, sqrt(3)]) at the interval's ends,
//   with
//                the device's float evaluation (vsm: one correctly rounded multiply, 2^-24 relative; esm:
//                exp's (3 + 2|x|) ulps and its argument's rounding), then the format's rounding (for 16-bit
//                float one ulp, 2^-10 relative: conversions may round to nearest or toward zero; plus 2^-24
//                absolute for subnormals).
//   each blur pass: the weighted sum (1 4 6 4 1) / 16 of the neighbours' intervals (cube::neighbour_texel,
//   the
//                shader's addressing), widened by the float sum's rounding in any order or fused form,
//                gamma_5 = 5 u / (1 - 5 u) of the sum of magnitudes, then the format's rounding again.
//   subnormals:  binary32 subnormals may be flushed to zero by any operation (GLSL 4.60 4.7.1, the Vulkan
//                environment's precision rules): 2^-126 absolute per value and per product.
// Nothing here depends on how a device rasterises: the check holds on every conformant implementation and
// fails a device that stores other moments (not squared, a wrong warp), skips or misplaces a blur tap, or
// blurs one face less than the others.

#include <cstdint>
#include <string>

#include "backends/backend.h"

namespace omnishadow::bench {

struct MomentsReport {
  uint64_t values = 0;      // texel channels checked
  uint64_t outside = 0;     // outside their bound
  uint64_t non_finite = 0;  // NaN or Inf (an overflowed warp): counted apart, also a failure
  // The worst value outside its bound, to name in the finding.
  int face = -1, s = -1, t = -1, channel = -1;
  double got = 0.0, low = 0.0, high = 0.0;
  bool ok() const { return outside == 0 && non_finite == 0; }
};

// Needs a full read-back (Images::has_full_cube and Images::moments); `storage` a moments storage, `tuning`
// the case's (its exponent, floor and distance scale decide the moments).
MomentsReport check_moments(const Images& images, Storage storage, DepthFormat depth_format,
                            const MomentsTuning& tuning = {});
std::string describe(const MomentsReport& r);

}  // namespace omnishadow::bench
