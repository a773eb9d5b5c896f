#pragma once
// What a conformant rasteriser may store in a shadow-map texel, for the cube and 2D-map texel truths.
//
// The rasteriser snaps every vertex to its sub-pixel grid (GL_SUBPIXEL_BITS, VkPhysicalDeviceLimits::
// subPixelPrecisionBits: 8 on llvmpipe and on an NVIDIA H100, at least 4 anywhere) and then decides coverage
// and interpolates exactly at the texel centre. A snapped triangle is the exact one with each vertex moved by
// e_i, |e_i| <= one step 2^-bits (per axis, in texels; one full step covers rounding and truncation alike).
// At a centre P inside the snapped triangle the interpolated value is sum b_i' z_i with barycentrics b_i' >=
// 0 of P in the snapped triangle, so it is the exact triangle's value at P - sum b_i' e_i: at a point within
// one step of P. So a texel may hold the exact first-hit value of any point of the square of half-side
// `reach` around its centre:
//   - on a plane the value is affine in the texel coordinates (window depth) or nearly so over 1e-2 texel (a
//     distance), so its extremes over the square are at the corners: that is the slope term, as polygon
//     offset's slope factor is, and it grows without limit at grazing angles where the plane is nearly
//     edge-on;
//   - a silhouette edge that crosses the square has corners on both sides (a line through a convex square's
//     interior separates its corners), so either side's value is allowed: a surface or nothing, near or far.
//     The surface's own extreme then lies on its edge, inside the square and beyond every corner that meets
//     it: a steep triangle whose edge passes between the centre and a corner stores a value none of the
//     corners hold (seen on the hall at 16-texel faces, where a texel spans four times a 64-texel one's
//     slope). So each surface a corner or the centre meets counts with its plane's range over the whole
//     square, the plane at the four corners (TexelSample::plane_lo, plane_hi); a paraboloid's triangles are
//     no planes in its warp and count by the values at the corners alone.
// The checks therefore accept a stored value within the storage's bound of the centre's exact value, or else
// within that bound of the range those surfaces span over the square (where some corner meets a surface) or
// "nothing" (where some corner meets none). The corner rays are cast only for texels that fail the centre,
// so the cost stays with the few texels at edges. The storage's bound is its quantisation step plus fp32
// interpolation error.
//
// reach = 2 steps: one for the device's own snapping, one of headroom so that the test-only perturbation
// (--raster-perturb: every vertex moved by up to one step on top of a rounding rasteriser's half step, 1.5
// steps in all) stays inside. 2/256 of a texel on 8-bit devices: the mutants move values by half a texel or
// more. Not covered: a triangle corner poking into the square without reaching a corner ray (a sliver tip
// within 2^-7 texel of a centre); rare, and the per-case limit of 0.1% of texels absorbs it.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace omnishadow::bench {

inline constexpr double kRasterReachSteps = 2.0;
inline double raster_reach_texels(int subpixel_bits) {
  return kRasterReachSteps * std::ldexp(1.0, -subpixel_bits);
}

// An exact value at one point: a surface and its value (distance or window depth), or nothing along the ray.
struct TexelSample {
  bool surface = false;
  double value = 0.0;
  // The range this point's surface spans over the whole reach square (its plane at the square's corners and
  // along the centre's ray; -1: none known): what a fragment at the centre may interpolate when the
  // triangle's coverage reaches the centre from anywhere in the square, past its own edge included.
  double plane_lo = -1.0, plane_hi = -1.0;
};

// One wrong texel, for the report: which, what it held, what the centre's ray says, and how far (in texels)
// the nearest depth discontinuity lies from its centre (probed at 1/256 .. 2 texels; -1 when none within 2).
struct TexelFinding {
  int layer = 0;  // cube face, or map index
  int s = 0, t = 0;
  double got = 0.0, want = 0.0;  // stored and exact at the centre; "nothing" is written as -1
  double edge_texels = -1.0;
};

enum class TexelVerdict { ok, wrong, spurious, missing };

// The verdict on `got` given the centre's exact sample, whether two values agree within the storage's bound
// (`agree(stored, exact)`), and the exact samples at the square's corners, with the ranges their surfaces
// span over the square (`corners()`, called only when needed; it may add the centre's own sample).
template <typename Agree, typename Corners>
TexelVerdict judge_texel(const TexelSample& got, const TexelSample& centre, Agree agree, Corners corners) {
  if (got.surface == centre.surface && (!got.surface || agree(got.value, centre.value)))
    return TexelVerdict::ok;
  const std::vector<TexelSample> reach = corners();
  bool any_nothing = !centre.surface;
  double lo = centre.surface ? centre.value : HUGE_VAL, hi = centre.surface ? centre.value : -HUGE_VAL;
  for (const TexelSample& c : reach) {
    if (!c.surface) {
      any_nothing = true;
      continue;
    }
    lo = std::min(lo, c.value), hi = std::max(hi, c.value);
    if (c.plane_lo >= 0.0) lo = std::min(lo, c.plane_lo), hi = std::max(hi, c.plane_hi);
  }
  if (!got.surface && any_nothing) return TexelVerdict::ok;
  if (got.surface && lo <= hi) {
    const double clamped = std::clamp(got.value, lo, hi);
    if (clamped == got.value || agree(got.value, clamped)) return TexelVerdict::ok;
  }
  if (got.surface && !centre.surface) return TexelVerdict::spurious;
  if (!got.surface && centre.surface) return TexelVerdict::missing;
  return TexelVerdict::wrong;
}

// The corners of the square of half-side `reach` around (cs, ct), in continuous texel coordinates.
template <typename Cast>
std::vector<TexelSample> reach_corners(double cs, double ct, double reach, Cast cast) {
  return {cast(cs - reach, ct - reach), cast(cs + reach, ct - reach), cast(cs - reach, ct + reach),
          cast(cs + reach, ct + reach)};
}

// The distance in texels from (cs, ct) to the nearest depth discontinuity, probed on rings of 8 rays at 1/256
// to 2 texels: the first radius at which a probe meets nothing where the centre meets a surface (or the
// reverse), or a value more than 5% away from the centre's. -1 when none within 2 texels.
template <typename Cast>
double edge_distance_texels(double cs, double ct, Cast cast) {
  const TexelSample centre = cast(cs, ct);
  for (double r : {1.0 / 256, 1.0 / 64, 1.0 / 16, 0.25, 0.5, 1.0, 2.0})
    for (int k = 0; k < 8; ++k) {
      const double a = k * 0.78539816339744831;
      const TexelSample p = cast(cs + r * std::cos(a), ct + r * std::sin(a));
      if (p.surface != centre.surface) return r;
      if (p.surface && std::fabs(p.value - centre.value) > 0.05 * std::max(std::fabs(centre.value), 1e-6))
        return r;
    }
  return -1.0;
}

// Keeps the `capacity` findings with the largest |got - want| (nothing counted as the larger of the two).
class WorstTexels {
 public:
  explicit WorstTexels(size_t capacity = 5) : capacity_(capacity) {}
  void add(const TexelFinding& f) {
    list_.push_back(f);
    std::sort(list_.begin(), list_.end(),
              [](const TexelFinding& a, const TexelFinding& b) { return size(a) > size(b); });
    if (list_.size() > capacity_) list_.pop_back();
  }
  std::vector<TexelFinding>& list() { return list_; }

 private:
  static double size(const TexelFinding& f) {
    return f.got < 0 || f.want < 0 ? std::max(std::fabs(f.got), std::fabs(f.want))
                                   : std::fabs(f.got - f.want);
  }
  size_t capacity_;
  std::vector<TexelFinding> list_;
};

// " worst: +Y (12, 40) got 3.1 want 5.4, edge 0.0039 texels away" (layer names from `layer_name`).
std::string describe_worst(const std::vector<TexelFinding>& worst, const std::string& layer_prefix,
                           const char* const* layer_names);

}  // namespace omnishadow::bench
