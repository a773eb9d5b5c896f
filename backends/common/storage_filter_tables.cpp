#include "backends/common/storage_filter_tables.h"

#include <cmath>

namespace omnishadow {

ColourFormat colour_format(Storage s, DepthFormat depth_format) {
  const StorageTraits& row = traits(s);
  if (row.colour_channels == 0) return ColourFormat::none;
  if (row.colour_channels == 1) return ColourFormat::r32f;
  const bool half = row.half_precision_at_d16 && depth_format == DepthFormat::d16;
  return half ? ColourFormat::rg16f : ColourFormat::rg32f;
}

int colour_format_bytes(ColourFormat f) {
  switch (f) {
    case ColourFormat::none: return 0;
    case ColourFormat::r32f: return 4;
    case ColourFormat::rg32f: return 8;
    case ColourFormat::rg16f: return 4;
  }
  return 0;
}

Storage storage_for(Filter filter, Storage storage) { return traits(filter).own_storage.value_or(storage); }

bool filter_reads(Filter filter, Storage storage) {
  const std::optional<Storage> own = traits(filter).own_storage;
  return own ? *own == storage : traits(storage).moments == MomentKind::none;
}

float moments_min_variance(ColourFormat f) {
  return 4.0f * std::ldexp(1.0f, f == ColourFormat::rg16f ? -11 : -24);
}

std::array<float, 4> moments_clear_value(Storage s) {
  switch (traits(s).moments) {
    case MomentKind::none: break;
    case MomentKind::vsm: return {1.0f, 1.0f, 0.0f, 0.0f};  // z = 1, z^2 = 1
  }
  return {0.0f, 0.0f, 0.0f, 0.0f};
}

}  // namespace omnishadow
