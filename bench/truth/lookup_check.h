#pragma once
// The lookup check: did the lighting pass read the texels the cube-map rule names? For the filters whose taps
// are NEAREST lookups of a stored distance (hard, pcf_grid64, pcf_disk20), every covered pixel's shadow
// factor is replayed on the host from what was read back: the pixel's world position (the check variant
// writes the very value the shader used), the light, the kernel of shaders/shadow_filters.glsl (its disk
// table parsed from the embedded source, so there is one copy), and the cube's stored distances. A tap may
// read any texel the rule allows within the device's guarantees, so each tap gives a set of outcomes, and the
// pixel a range [low, high] that the device's value must lie in:
//   - texel choice: the direction's face coordinate s * size may be off by 2^-subTexelPrecisionBits of a
//   texel
//     (Vulkan's limit; its minimum, 4 bits, is assumed for GL, which states none) plus the float rounding of
//     the direction (two roundings of its largest component) and of the division (2.5 ulp, GLSL's precision);
//     every texel within that of the exact point is allowed, and both faces where the major axis is that
//     close to a tie or the point that close to the edge between them (a seamless cube's NEAREST lookup that
//     rounds onto an edge reads the adjacent face's texel);
//   - comparison: current - bias > stored may go either way within 1e-4 of the operands' size (the GL rule's
//   1 part
//     in 1e5 per operation, about ten operations from position to comparison).
//   - range: a pixel farther from the light than the far plane (Images::light_far) is reported 0
//     (lighting.frag), one within float
//     rounding of it either 0 or what its taps give.
// Anything else is a lookup that reads other texels than the rule's: a flipped axis, a face read from another
// layer, a half-texel offset, a kernel of another size. The texel truths (cube_truth.h) check what was
// stored; this checks what was read.

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend.h"

namespace omnishadow::bench {

struct LookupInputs {
  Filter filter = Filter::hard;
  BiasMode bias =
      BiasMode::tutorial;  // tutorial or zero (the slope bias reads the normal, which is not read back)
  glm::dvec3 light{0.0};   // the light at the check frame, in the scene's (possibly rebased) space
  glm::dvec3 camera{0.0};  // pcf_disk20's radius grows with the distance to the viewer
  double far_plane = 1.0;  // the far plane the cube was rendered with (Images::light_far)
  double pcf_scale = 1.0;
  int subtexel_bits = 4;
};

struct LookupReport {
  uint64_t pixels = 0;   // covered pixels replayed
  uint64_t outside = 0;  // pixels whose shadow factor no allowed texel choice or comparison gives
  uint64_t taps = 0, ambiguous_taps = 0;
  struct Example {
    int x = 0, y = 0;  // pixel, row 0 at the bottom (GL window convention, as read back)
    float got = 0.0f;
    double low = 0.0, high = 0.0;
  };
  std::vector<Example> examples;  // the first few outside
  bool ok() const { return outside == 0; }
  double outside_percent() const { return pixels ? 100.0 * double(outside) / double(pixels) : 0.0; }
};

// Why the check does not apply to a case (empty: it applies): a filter whose taps are not NEAREST lookups of
// a distance, the slope bias or normal offset (they read the surface normal), hardware depth (converted along
// the tap's own direction), no full cube read back, no point light.
std::string lookup_check_skip_reason(const CaseConfig& c, const Images& images, bool has_point_light);

LookupReport check_lookups(const Images& images, const LookupInputs& in);
std::string describe(const LookupReport& r);

// shaders/shadow_filters.glsl's kDiskDirections, read from the embedded source (throws std::runtime_error if
// the table cannot be found: the shader and this replay must change together).
const std::vector<glm::dvec3>& disk_directions();

}  // namespace omnishadow::bench
