#pragma once
// Storages and filters as rows of two tables, as techniques.h is for techniques. The matrix, the shader
// variants, the memory budget, the truth bounds, the results and both backends read these rows; a backend
// only maps a row's colour format to its API's format.
//
// Adding a lookup-only filter: a Filter value (case_config.h), a row in kFilterTable (its spelling first) and
// its branch of shadow_factor() in shaders/shadow_filters.glsl. Adding a moments filter: also a Storage value
// and a row in kStorageTable naming its moments, its branch of shaders/moments.glsl (the
// moments written and the lookup), and the moments' C++ form in bench/truth/moments_check.cpp that checks
// them.

#include <array>
#include <optional>
#include <string_view>
#include <type_traits>

#include "backends/common/case_config.h"

namespace omnishadow {

// How the cube the checks read back turns into distances (the depth attachment, or the colour for r32f).
enum class DistanceEncoding {
  linear_depth,      // distance / far as depth (UNORM or float): distance = stored x far
  colour_distance,   // world units in an R32F colour cube cleared to FLT_MAX
  projective_depth,  // the rasteriser's own depth: back through the projection along the texel's direction
};

// What a colour cube beside the depth holds.
enum class MomentKind {
  none,  // no colour cube, or r32f distances
  vsm,   // (z, z^2) of z = distance / far (Donnelly & Lauritzen 2006)
  esm,   // exp(c min(z, 1)), c = moments_parameter (Annen et al. 2008)
  evsm,  // e^(cz), e^(2cz) [, -e^(-cz), e^(-2cz)] of min(z, 1) (Lauritzen & McCool 2008): 2 or 4 channels
  msm,   // z, z^2, z^3, z^4 of min(z, 1) (Peters & Klein 2015)
};

// A colour cube's format; each backend maps it to its API's (GL internal format, VkFormat).
enum class ColourFormat { none, r32f, rg32f, rg16f, r16f, rgba32f, rgba16f };

struct StorageTraits {
  Storage storage;
  std::string_view name;       // CLI, case ids, JSON
  std::string_view define;     // STORAGE_* in the shaders (CMakeLists.txt compiles SPIR-V per storage)
  DistanceEncoding checked;    // what the checked cube stores
  bool colour_checked;         // the checked cube is the colour attachment (else the depth attachment)
  bool fragment_depth;         // the shadow pass writes distance / far as its depth (else the rasteriser's)
  int colour_channels;         // channels of the colour cube beside the depth; 0: none
  bool half_precision_at_d16;  // with --depth-format d16 the colour cube is 16-bit float (moments' precision
                               // axis)
  MomentKind moments;
};

inline constexpr std::array<StorageTraits, 8> kStorageTable = {{
    {Storage::linear_depth, "linear_depth", "STORAGE_LINEAR_DEPTH", DistanceEncoding::linear_depth, false,
     true, 0, false, MomentKind::none},
    {Storage::r32f_distance, "r32f_distance", "STORAGE_R32F_DISTANCE", DistanceEncoding::colour_distance,
     true, false, 1, false, MomentKind::none},
    {Storage::hardware_depth, "hardware_depth", "STORAGE_HARDWARE_DEPTH", DistanceEncoding::projective_depth,
     false, false, 0, false, MomentKind::none},
    // The depth is linear_depth's (the checks read it as such); the moments of the same z are the colour.
    {Storage::vsm_moments, "vsm_moments", "STORAGE_VSM_MOMENTS", DistanceEncoding::linear_depth, false, true,
     2, true, MomentKind::vsm},
    {Storage::esm_exp, "esm_exp", "STORAGE_ESM_EXP", DistanceEncoding::linear_depth, false, true, 1, true,
     MomentKind::esm},
    {Storage::evsm2_moments, "evsm2_moments", "STORAGE_EVSM2_MOMENTS", DistanceEncoding::linear_depth, false,
     true, 2, true, MomentKind::evsm},
    {Storage::evsm4_moments, "evsm4_moments", "STORAGE_EVSM4_MOMENTS", DistanceEncoding::linear_depth, false,
     true, 4, true, MomentKind::evsm},
    {Storage::msm_moments, "msm_moments", "STORAGE_MSM_MOMENTS", DistanceEncoding::linear_depth, false, true,
     4, true, MomentKind::msm},
}};

// How the lighting pass samples what the filter reads.
enum class FilterSampler {
  nearest,         // a distance cube, NEAREST, no compare
  linear_compare,  // samplerCubeShadow, LINEAR with compare: the hardware's 2x2 PCF on the depth cube
  linear_moments,  // the moments cube, LINEAR (moments average linearly: that is what makes them filterable)
};
// What runs between the shadow pass and the lighting pass, in the timed frame.
enum class Prefilter {
  none,
  separable_blur,  // shaders/moments_blur.comp: a 5-tap binomial blur along s, then along t, folded across
                   // seams
};

struct FilterTraits {
  Filter filter;
  std::string_view name;    // CLI, case ids, JSON
  std::string_view define;  // FILTER_* in shaders/shadow_filters.glsl
  bool soft;  // the default misclassification limit is the soft filters' (bench/truth/case_checks.h)
  FilterSampler sampler;
  std::optional<Storage>
      own_storage;  // a moments filter reads the moments it stores; nullopt: any distance storage
  Prefilter prefilter;
};

inline constexpr std::array<FilterTraits, 10> kFilterTable = {{
    {Filter::hard, "hard", "FILTER_HARD", false, FilterSampler::nearest, std::nullopt, Prefilter::none},
    {Filter::pcf_grid64, "pcf_grid64", "FILTER_PCF_GRID64", true, FilterSampler::nearest, std::nullopt,
     Prefilter::none},
    {Filter::pcf_disk20, "pcf_disk20", "FILTER_PCF_DISK20", true, FilterSampler::nearest, std::nullopt,
     Prefilter::none},
    // Soft only within one texel (a 2x2 bilinear weighting of four 0/1 comparisons): the hard limit applies.
    {Filter::hw_compare2x2, "hw_compare2x2", "FILTER_HW_COMPARE2X2", false, FilterSampler::linear_compare,
     std::nullopt, Prefilter::none},
    {Filter::pcss, "pcss", "FILTER_PCSS", true, FilterSampler::nearest, std::nullopt, Prefilter::none},
    {Filter::vsm, "vsm", "FILTER_VSM", true, FilterSampler::linear_moments, Storage::vsm_moments,
     Prefilter::separable_blur},
    {Filter::esm, "esm", "FILTER_ESM", true, FilterSampler::linear_moments, Storage::esm_exp,
     Prefilter::separable_blur},
    {Filter::evsm2, "evsm2", "FILTER_EVSM2", true, FilterSampler::linear_moments, Storage::evsm2_moments,
     Prefilter::separable_blur},
    {Filter::evsm4, "evsm4", "FILTER_EVSM4", true, FilterSampler::linear_moments, Storage::evsm4_moments,
     Prefilter::separable_blur},
    {Filter::msm, "msm", "FILTER_MSM", true, FilterSampler::linear_moments, Storage::msm_moments,
     Prefilter::separable_blur},
}};

constexpr const StorageTraits& traits(Storage s) {
  for (const StorageTraits& row : kStorageTable)
    if (row.storage == s) return row;
  return kStorageTable[0];  // unreachable: every Storage has a row (checked below)
}
constexpr const FilterTraits& traits(Filter f) {
  for (const FilterTraits& row : kFilterTable)
    if (row.filter == f) return row;
  return kFilterTable[0];
}
template <typename Table>
constexpr bool rows_in_enum_order(const Table& table) {
  for (size_t i = 0; i < table.size(); ++i) {
    if constexpr (std::is_same_v<typename Table::value_type, StorageTraits>) {
      if (static_cast<size_t>(table[i].storage) != i) return false;
    } else if (static_cast<size_t>(table[i].filter) != i) {
      return false;
    }
  }
  return true;
}
static_assert(rows_in_enum_order(kStorageTable), "kStorageTable lists the storages in enum order");
static_assert(rows_in_enum_order(kFilterTable), "kFilterTable lists the filters in enum order");

// The colour cube's format for the case (none without one): r32f for distances; moments in 32-bit float, or
// 16-bit float with d16 (the precision axis of the moments storages).
ColourFormat colour_format(Storage s, DepthFormat depth_format);
int colour_format_bytes(ColourFormat f);
// The storage a case of `filter` uses when the matrix names `storage`: a moments filter's own, else
// `storage`.
Storage storage_for(Filter filter, Storage storage);
// Whether `filter` can read `storage` (a moments filter only its own moments; the others only distances).
bool filter_reads(Filter filter, Storage storage);
bool is_half(ColourFormat f);  // a 16-bit float format
// The largest exponent c an exponential warp may have before the moments of z = 1 overflow the format: ln of
// its largest finite value for esm (88.7 float, 11.09 half), half of it for evsm, which stores e^(2cz).
float exponent_overflow_limit(Storage s, ColourFormat f);
// The moments' one parameter (frame.knobs.w), by storage and format, at the default tuning:
//   vsm: the variance floor as a fraction of m2, four units of the format's rounding (2^-24 for 32-bit float,
//        2^-11 for 16-bit), above what rounding leaves of m2 - m1^2 (about three units of m2) on a flat
//        surface;
//   esm: the exponent c, 0.9 of exponent_overflow_limit (79.8 for 32-bit float, 9.98 for 16-bit): exp(c z) of
//        z <= 1 stays finite, and the blur's averages never exceed their inputs;
//   evsm: the exponent c, 0.9 of its limit (39.9, 4.99);
//   msm:  the moment bias alpha towards (0.5, 0.5, 0.5, 0.5): 3e-5 for 32-bit float (Peters & Klein's), 1e-3
//   for
//         16-bit (their 16-bit form needs a quantisation transform this storage does not apply).
// The tuning's floor_scale multiplies vsm's and msm's; its exponent_fraction replaces the 0.9.
float moments_parameter(Storage s, ColourFormat f, const MomentsTuning& t = {});
// What the stored distance is multiplied by before its moments are taken: 1 (z = distance / far), or far with
// world_units (frame.moments_knobs.y).
float moments_distance_scale(const MomentsTuning& t, float far_plane);
// The value a moments cube is cleared to: the moments of z = 1 (nothing drawn: the far plane, as the depth's
// clear).
std::array<float, 4> moments_clear_value(Storage s, DepthFormat depth_format, const MomentsTuning& t,
                                         float far_plane);

}  // namespace omnishadow
