#pragma once
// Layout atlas: every point light's six cube faces as tiles of one 2D depth texture (one layer), as Godot,
// HDRP and Filament pack shadow maps. The one source of truth for where light k's face f lives, read by both
// backends (viewports, clears, read-back), the lighting pass's records (gpu::PointLightRecord::atlas_tile,
// shaders/shadow_filters.glsl's LAYOUT_ATLAS lookup) and the tests.
//
// A light owns a block of 3 x 2 tiles, face f at column f % 3 and row f / 3 (face order of cube_faces.h);
// each tile is the face's N x N texels inside a border of kAtlasBorder texels on every side. The lookup
// clamps a face's (s, t) to its texel centres, as face_array's sampler clamps at a layer's edge, so NEAREST
// taps never leave the face and a LINEAR tap reads a border texel only with weight 0 (within the sampler's
// sub-texel rounding): the border keeps a neighbour's texels out of that reach. Borders hold the clear value
// (nothing drawn: lit), cleared with the light's block. Texel rows as the faces': row 0 is t = 0.

#include <span>
#include <string>
#include <vector>

#include "backends/common/case_config.h"

namespace omnishadow::atlas {

inline constexpr int kBorder = 1;  // texels around each face's tile

struct Block {
  int x = 0, y = 0;   // the block's first texel (column, row) in the atlas
  int face_size = 0;  // N: each face's edge in texels
};

struct Plan {
  int width = 0, height = 0;  // the atlas in texels
  std::vector<Block> lights;  // light k's block
};

// A tile's edge with its borders, and a light's block in texels.
inline int tile_span(int face_size) { return face_size + 2 * kBorder; }
inline int block_width(int face_size) { return 3 * tile_span(face_size); }
inline int block_height(int face_size) { return 2 * tile_span(face_size); }

// Face f's first interior texel (its texel (0, 0)) in the atlas.
struct Texel {
  int x = 0, y = 0;
};
Texel face_origin(const Block& block, int face);

// Packs one block per light, face sizes as given (each light its own), in shelves: blocks sorted by size,
// largest first (ties in light order), placed left to right on rows as tall as their first block, the rows as
// wide as makes the atlas's longer side shortest (a device bounds each side). Deterministic: the same sizes
// always give the same plan. Throws std::invalid_argument for an empty list or a size below 1.
Plan pack(std::span<const int> face_sizes);

// The case's atlas: light k's faces at CaseConfig::cube_size (every light alike). Layout atlas only.
Plan plan_for(const CaseConfig& config);

// Why a plan does not fit a device's 2D textures of at most `max_size` texels a side (`limit`: the API's name
// for it); empty when it fits.
std::string too_large(const Plan& plan, int max_size, const std::string& limit);

}  // namespace omnishadow::atlas
