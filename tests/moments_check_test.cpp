// The moments blur's cube addressing (cube::neighbour_texel, mirrored by shaders/cube_texel.glsl) and the
// moments check (bench/truth/moments_check.h): it passes what a conformant device may store (a float replay
// of the shader, every value then moved by an ulp or two) and fails every planted bug.

#include "bench/truth/moments_check.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "backends/common/cube_faces.h"
#include "backends/common/storage_filter_tables.h"

namespace omnishadow {
namespace {

TEST(NeighbourTexel, StaysInsideAFace) {
  EXPECT_EQ(cube::neighbour_texel(3, 5, 6, 0, 2, 16), (cube::FaceTexel{3, 7, 6}));
  EXPECT_EQ(cube::neighbour_texel(3, 5, 6, 1, -2, 16), (cube::FaceTexel{3, 5, 4}));
}

// Past every edge of every face: the texel reached lies on another face, next to the edge (its direction
// within about one texel's angle of the source's), and one step back from it along one of its axes returns to
// the source.
TEST(NeighbourTexel, CrossesEachSeamOntoTheAdjacentTexelAndBack) {
  for (int size : {4, 7, 16}) {
    const double texel_angle = 2.0 / size;
    for (int face = 0; face < 6; ++face)
      for (int i = 0; i < size; ++i)
        for (int edge = 0; edge < 4; ++edge) {
          const int axis = edge / 2, k = edge % 2 ? 1 : -1;
          const int s = axis == 0 ? (k > 0 ? size - 1 : 0) : i, t = axis == 1 ? (k > 0 ? size - 1 : 0) : i;
          const cube::FaceTexel n = cube::neighbour_texel(face, s, t, axis, k, size);
          ASSERT_NE(n.face, face);
          ASSERT_TRUE(n.s >= 0 && n.s < size && n.t >= 0 && n.t < size);
          const glm::vec3 a = glm::normalize(cube::texel_direction(face, s, t, size));
          const glm::vec3 b = glm::normalize(cube::texel_direction(n.face, n.s, n.t, size));
          EXPECT_LT(std::acos(std::min(1.0f, glm::dot(a, b))), 1.5 * texel_angle)
              << face << " " << s << " " << t;
          int back = 0;
          for (int axis2 = 0; axis2 < 2; ++axis2)
            for (int k2 : {-1, 1})
              back += cube::neighbour_texel(n.face, n.s, n.t, axis2, k2, size) == cube::FaceTexel{face, s, t};
          EXPECT_EQ(back, 1) << "face " << face << " (" << s << ", " << t << ") edge " << edge;
        }
  }
}

// A device's moments, replayed in float as shaders/moments.glsl and moments_blur.comp compute them; `bug`
// plants a fault into the replay.
enum class Bug { none, not_squared, face_unblurred, shifted_tap, clamped_seam, nan, exponent_sign };

// The storage's moments of z in float, as the shader computes them (esm: exp of the float product c z) with
// the case's tuning (its exponent; vsm's distance scale `scale`).
std::vector<float> device_moments(Storage storage, float z, Bug bug, const MomentsTuning& tuning,
                                  float scale) {
  if (storage == Storage::esm_exp) {
    const float c = moments_parameter(storage, ColourFormat::r32f, tuning);
    return {std::exp((bug == Bug::exponent_sign ? -c : c) * std::min(z, 1.0f))};
  }
  if (storage == Storage::msm_moments) {
    const float c = std::min(z, 1.0f), c2 = c * c;
    return {c, c2, c2 * c, c2 * c2};
  }
  if (storage == Storage::evsm2_moments || storage == Storage::evsm4_moments) {
    const float c = moments_parameter(storage, colour_format(storage, DepthFormat::d32f), tuning);
    const float p = std::exp(c * std::min(z, 1.0f)), n = std::exp(-c * std::min(z, 1.0f));
    if (storage == Storage::evsm2_moments) return {p, p * p};
    return {p, p * p, -n, n * n};
  }
  const float d = z * scale;
  return {d, bug == Bug::not_squared ? d : d * d};
}

// Flushes binary32 subnormals to zero, as a device may in and out of every operation.
void flush_subnormals(std::array<std::vector<float>, 6>& m) {
  for (auto& face : m)
    for (float& v : face)
      if (std::fpclassify(v) == FP_SUBNORMAL) v = 0.0f;
}

Images device_images(int size, Bug bug, Storage storage = Storage::vsm_moments,
                     const MomentsTuning& tuning = {}, bool flush = false) {
  Images img;
  img.cube_size = size;
  img.light_far = 25.0f;
  const int channels = traits(storage).colour_channels;
  img.moment_channels = channels;
  std::array<std::vector<float>, 6> m;
  for (int f = 0; f < 6; ++f) {
    auto& d = img.cube_distance[size_t(f)];
    for (int t = 0; t < size; ++t)
      for (int s = 0; s < size; ++s) {
        // A wall with a box in front of it on some faces, nothing drawn (far) on face 3: edges to blur
        // across.
        float z = 0.4f + 0.02f * float(s) / float(size) + 0.05f * float(f);
        if (s > size / 3 && s < size / 2 && t > size / 4) z = 0.15f;
        if (f == 3) z = 1.0f;
        d.push_back(z * img.light_far);
        for (float v : device_moments(storage, z, bug, tuning, moments_distance_scale(tuning, img.light_far)))
          m[size_t(f)].push_back(v);
      }
  }
  if (flush) flush_subnormals(m);
  for (int axis = 0; axis < 2; ++axis) {
    std::array<std::vector<float>, 6> out = m;
    const float w[5] = {1.0f / 16, 4.0f / 16, 6.0f / 16, 4.0f / 16,
                        1.0f / 16};  // as moments_blur.comp: pre-scaled
    for (int f = 0; f < 6; ++f) {
      if (bug == Bug::face_unblurred && f == 2) continue;
      for (int t = 0; t < size; ++t)
        for (int s = 0; s < size; ++s)
          for (int c = 0; c < channels; ++c) {
            float sum = 0.0f;
            for (int k = -2; k <= 2; ++k) {
              int kk = bug == Bug::shifted_tap ? k + 1 : k;
              cube::FaceTexel n = cube::neighbour_texel(f, s, t, axis, kk, size);
              if (bug == Bug::clamped_seam) {
                int ss = axis == 0 ? std::clamp(s + k, 0, size - 1) : s,
                    tt = axis == 1 ? std::clamp(t + k, 0, size - 1) : t;
                n = {f, ss, tt};
              }
              sum += w[k + 2] * m[size_t(n.face)]
                                 [(size_t(n.t) * size_t(size) + size_t(n.s)) * size_t(channels) + size_t(c)];
            }
            out[size_t(f)][(size_t(t) * size_t(size) + size_t(s)) * size_t(channels) + size_t(c)] = sum;
          }
    }
    m = out;
    if (flush) flush_subnormals(m);
  }
  if (bug == Bug::nan) m[4][10] = std::nanf("");
  img.moments = m;
  return img;
}

TEST(MomentsCheck, PassesTheDevicesRoundingAndAnUlpEitherWay) {
  for (Storage storage : {Storage::vsm_moments, Storage::esm_exp, Storage::evsm2_moments,
                          Storage::evsm4_moments, Storage::msm_moments})
    for (int size : {4, 16}) {
      Images img = device_images(size, Bug::none, storage);
      EXPECT_TRUE(bench::check_moments(img, storage, DepthFormat::d32f).ok()) << to_string(storage);
      // Any order of the sums, fused or not, moves a value by at most a few ulps: move every value by two.
      for (auto& face : img.moments)
        for (size_t i = 0; i < face.size(); ++i)
          face[i] = std::nextafter(std::nextafter(face[i], i % 2 ? 2.0f : -2.0f), i % 2 ? 2.0f : -2.0f);
      const bench::MomentsReport r = bench::check_moments(img, storage, DepthFormat::d32f);
      EXPECT_TRUE(r.ok()) << to_string(storage) << ": " << bench::describe(r);
      EXPECT_EQ(r.values, 6u * size_t(size) * size_t(size) * size_t(img.moment_channels));
    }
}

// exp's error grows with its argument x = c z (3 + 2|x| ulps, plus |x| / 2 ulps of the argument's rounding):
// in this scene z >= 0.15 at c = 79.8 gives x >= 12 and at least 39 ulps of allowance, so a device 30 ulps
// off everywhere passes; 1000 ulps off (beyond the largest allowance, about 160 ulps at z = 0.65) fails.
TEST(MomentsCheck, EsmAllowsExpsPrecisionAndCatchesAFlippedExponent) {
  auto scaled = [](float ulps) {
    Images img = device_images(16, Bug::none, Storage::esm_exp);
    for (auto& face : img.moments)
      for (float& v : face) v *= 1.0f + ulps * 0x1p-23f;
    return img;
  };
  EXPECT_TRUE(bench::check_moments(scaled(30.0f), Storage::esm_exp, DepthFormat::d32f).ok());
  EXPECT_FALSE(bench::check_moments(scaled(1000.0f), Storage::esm_exp, DepthFormat::d32f).ok());
  EXPECT_FALSE(bench::check_moments(device_images(16, Bug::exponent_sign, Storage::esm_exp), Storage::esm_exp,
                                    DepthFormat::d32f)
                   .ok());
  Images nan = device_images(16, Bug::nan, Storage::esm_exp);
  EXPECT_EQ(bench::check_moments(nan, Storage::esm_exp, DepthFormat::d32f).non_finite, 1u);
}

TEST(MomentsCheck, FailsEveryPlantedBug) {
  for (Bug bug : {Bug::not_squared, Bug::face_unblurred, Bug::shifted_tap, Bug::clamped_seam, Bug::nan}) {
    const bench::MomentsReport r =
        bench::check_moments(device_images(16, bug), Storage::vsm_moments, DepthFormat::d32f);
    EXPECT_FALSE(r.ok()) << "bug " << int(bug);
  }
}

// 16-bit moments (d16): the format's rounding is in the bound, and a device storing float-precision values
// passes.
TEST(MomentsCheck, SixteenBitMomentsAllowTheirRounding) {
  Images img = device_images(16, Bug::none);
  for (auto& face : img.moments)
    for (float& v : face) v *= 1.0f - 0x1p-11f;  // half a binary16 ulp: within one rounding, either mode
  EXPECT_TRUE(bench::check_moments(img, Storage::vsm_moments, DepthFormat::d16).ok());
  EXPECT_FALSE(bench::check_moments(img, Storage::vsm_moments, DepthFormat::d32f).ok());
}

// The extremes suite's tunings (MomentsTuning): the check replays the case's exponent and distance scale.
// EVSM at 0.99 of the overflow limit: e^(-2cz) at z = 1 is subnormal (7e-39), which a device may flush to
// zero - allowed; at 1.01 e^(2cz) is infinite - caught; a device that ignores the tuning (the default
// exponent, normalised distances) fails it.
TEST(MomentsCheck, FollowsTheTuningAllowsSubnormalFlushAndCatchesOverflow) {
  const MomentsTuning below{.exponent_fraction = 0.99f}, above{.exponent_fraction = 1.01f};
  const Images flushed = device_images(16, Bug::none, Storage::evsm4_moments, below, true);
  size_t zeros = 0;
  for (const auto& face : flushed.moments) zeros += size_t(std::count(face.begin(), face.end(), 0.0f));
  EXPECT_GT(zeros, 0u) << "the scene reaches z = 1, where the negative warp is subnormal";
  const bench::MomentsReport r =
      bench::check_moments(flushed, Storage::evsm4_moments, DepthFormat::d32f, below);
  EXPECT_TRUE(r.ok()) << bench::describe(r);
  EXPECT_FALSE(bench::check_moments(flushed, Storage::evsm4_moments, DepthFormat::d32f).ok())
      << "default exponent";
  const Images overflowed = device_images(16, Bug::none, Storage::evsm4_moments, above);
  EXPECT_GT(bench::check_moments(overflowed, Storage::evsm4_moments, DepthFormat::d32f, above).non_finite,
            0u);

  const MomentsTuning world{.world_units = true};
  const Images in_world = device_images(16, Bug::none, Storage::vsm_moments, world);
  EXPECT_TRUE(bench::check_moments(in_world, Storage::vsm_moments, DepthFormat::d32f, world).ok());
  EXPECT_FALSE(
      bench::check_moments(device_images(16, Bug::none), Storage::vsm_moments, DepthFormat::d32f, world)
          .ok());
  EXPECT_FALSE(bench::check_moments(in_world, Storage::vsm_moments, DepthFormat::d32f).ok());
}

}  // namespace
}  // namespace omnishadow
