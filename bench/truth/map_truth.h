#pragma once
// Truth for the 2D shadow maps of spot and directional lights, as bench/truth/cube_truth.h is for the cube:
// for texel centres of every map (all of them up to 128 a side, above that a regular grid of 128 x 128), the
// window depth of the first surface the map pass keeps along the texel's ray, by casting it against the
// scene's triangles. The ray comes from unprojecting the texel centre with the map's own view-projection at
// the near and far planes (texel row 0 is NDC y = -1 in both APIs), so a wrong map matrix does not fool it
// only if the matrix is what is being tested: it catches a broken depth range, an upside-down or mirrored
// map, culling of the wrong faces and a map that was not rendered or cleared.

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "backends/backend.h"
#include "backends/common/cube_faces.h"
#include "backends/reference/ray_caster.h"
#include "bench/truth/texel_bounds.h"

namespace omnishadow::bench {

inline constexpr int kMapTruthGrid = 128;
// A case whose maps have more than this share of checked texels wrong (and more than one) fails its check.
inline constexpr double kMapTexelLimitPercent = 0.1;

struct MapTruth {
  int size = 0;
  int stride = 1;
  // Per map light, per checked texel (row-major): the expected window depth in [0, 1]; 1 where nothing is hit
  // (what the pass clears to).
  std::vector<std::vector<float>> depth;
  // The exact window depth through any point of map `m` in continuous texel coordinates (texel k's centre at
  // k + 0.5), 1 where nothing is met: the checks cast off-centre rays through it (texel_bounds.h).
  std::function<double(size_t m, double x, double y)> cast;
  // cast(m, x, y) as a sample of the reach square of half-side `reach` around (cx, cy): with the range the
  // surface met spans over that square (texel_bounds.h; window depths).
  std::function<TexelSample(size_t m, double x, double y, double cx, double cy, double reach)> sample;
};
MapTruth compute_map_truth(const reference::RayCaster& caster, const scene::Scene& scene, int frame,
                           int map_size, cube::DepthRange range);

struct MapTexelReport {
  int stride = 1;
  uint64_t texels = 0;
  uint64_t wrong = 0;      // both a surface, depths apart beyond the bound
  uint64_t spurious = 0;   // a surface stored where the ray meets none
  uint64_t missing = 0;    // nothing stored where the ray meets a surface
  double max_error = 0.0;  // largest |stored - exact| window depth where both are a surface
  std::vector<uint64_t> bad_per_map;
  double reach_texels = 0.0;        // the sub-pixel reach the bound allowed
  std::vector<TexelFinding> worst;  // the largest wrong texels (layer = map), window depths
  uint64_t bad() const { return wrong + spurious + missing; }
  double bad_percent() const { return texels ? 100.0 * double(bad()) / double(texels) : 0.0; }
};
// A texel passes when its stored depth agrees with the exact one at its centre or at some point within the
// rasteriser's reach (texel_bounds.h). Two depths agree within two steps of the depth format (UNORM 2^-bits,
// D32F 2^-23 relative) plus 1e-5 for the rasteriser's interpolation against the ray's float arithmetic.
MapTexelReport check_map_texels(const MapTruth& truth, const Images& images, DepthFormat format,
                                int subpixel_bits);

// "map_texels: 3.1% of 16384 texels wrong (map 0 3.1%), max error 0.02" for a finding.
std::string describe(const MapTexelReport& r);

}  // namespace omnishadow::bench
