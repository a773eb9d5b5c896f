#include "backends/common/storage_filter_tables.h"

#include <cmath>
#include <limits>

namespace omnishadow {

ColourFormat colour_format(Storage s, DepthFormat depth_format) {
  const StorageTraits& row = traits(s);
  if (row.colour_channels == 0) return ColourFormat::none;
  const bool half = row.half_precision_at_d16 && depth_format == DepthFormat::d16;
  if (row.colour_channels == 1) return half ? ColourFormat::r16f : ColourFormat::r32f;
  if (row.colour_channels == 4) return half ? ColourFormat::rgba16f : ColourFormat::rgba32f;
  return half ? ColourFormat::rg16f : ColourFormat::rg32f;
}

int colour_format_bytes(ColourFormat f) {
  switch (f) {
    case ColourFormat::none:
      return 0;
    case ColourFormat::r32f:
      return 4;
    case ColourFormat::rg32f:
      return 8;
    case ColourFormat::rg16f:
      return 4;
    case ColourFormat::r16f:
      return 2;
    case ColourFormat::rgba32f:
      return 16;
    case ColourFormat::rgba16f:
      return 8;
  }
  return 0;
}

Storage storage_for(Filter filter, Storage storage) { return traits(filter).own_storage.value_or(storage); }

bool filter_reads(Filter filter, Storage storage) {
  const std::optional<Storage> own = traits(filter).own_storage;
  return own ? *own == storage : traits(storage).moments == MomentKind::none;
}

bool is_half(ColourFormat f) {
  return f == ColourFormat::rg16f || f == ColourFormat::r16f || f == ColourFormat::rgba16f;
}

float exponent_overflow_limit(Storage s, ColourFormat f) {
  const float log_max = std::log(is_half(f) ? 65504.0f : std::numeric_limits<float>::max());
  return traits(s).moments == MomentKind::esm ? log_max : 0.5f * log_max;  // evsm stores e^(2cz)
}

float moments_parameter(Storage s, ColourFormat f, const MomentsTuning& t) {
  const bool half = is_half(f);
  switch (traits(s).moments) {
    case MomentKind::vsm:
      return t.floor_scale * 4.0f * std::ldexp(1.0f, half ? -11 : -24);
    case MomentKind::esm:
    case MomentKind::evsm:
      return t.exponent_fraction * exponent_overflow_limit(s, f);
    case MomentKind::msm:
      return t.floor_scale * (half ? 1e-3f : 3e-5f);
    case MomentKind::none:
      break;
  }
  return 0.0f;
}

float moments_distance_scale(const MomentsTuning& t, float far_plane) {
  return t.world_units ? far_plane : 1.0f;
}

std::array<float, 4> moments_clear_value(Storage s, DepthFormat depth_format, const MomentsTuning& t,
                                         float far_plane) {
  const float c = moments_parameter(s, colour_format(s, depth_format), t);
  switch (traits(s).moments) {
    case MomentKind::none:
      break;
    case MomentKind::vsm: {  // z = 1, z^2 = 1, in world units far and far^2
      const float d = moments_distance_scale(t, far_plane);
      return {d, d * d, 0.0f, 0.0f};
    }
    case MomentKind::esm:
      return {std::exp(c), 0.0f, 0.0f, 0.0f};
    case MomentKind::evsm: {
      const float p = std::exp(c), n = std::exp(-c);
      return {p, p * p, -n, n * n};  // a 2-channel cube keeps the first two
    }
    case MomentKind::msm:
      return {1.0f, 1.0f, 1.0f, 1.0f};
  }
  return {0.0f, 0.0f, 0.0f, 0.0f};
}

}  // namespace omnishadow
