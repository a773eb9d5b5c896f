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

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "backends/common/case_config.h"
#include "scenes/scene.h"

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
// The same shelves within a width x height atlas already allocated (a re-plan: the texture keeps its size):
// rows as wide as the atlas or as 1, 2, ... of the largest block, the first that fits by pack's order; the
// plan's width and height are the atlas's. None when no shelf width fits.
std::optional<Plan> pack_into(std::span<const int> face_sizes, int width, int height);

// Each light's face size for the case (CaseConfig::atlas_tiles): --cube for every light (uniform), or by
// distance: --cube halved round(log2(d / range)) times, at most kMaxHalvings, where d is the light's distance
// from the camera at the frame the tiles are planned for (frame 0, or the re-plan's: plan_at; none within its
// range). A light's range sphere subtends about range / d of the
// view, so its texels a side follow its share of the screen, as engines size atlas slots by screen coverage.
inline constexpr int kMaxHalvings = 3;
// Point light k's distance from the camera at `frame` over its range: the inverse of its range sphere's share
// of the view (what by_distance sizes by, and what the checks pick their farthest light by).
double distance_over_range(const scene::Scene& scene, int light, int frame = 0);
// by_coverage: the share of a width x height view that point light k's range sphere covers at `frame`, by its
// projected bounding rectangle (1 with the camera inside the range, 0 out of view); each light's faces get
// --cube x sqrt(coverage) times a scale, powers of two from kMinCoverageFace to --cube, the largest scale
// whose atlas fits budget_texels(config).
double screen_coverage(const scene::Scene& scene, int light, int width, int height, int frame = 0);
inline constexpr int kMinCoverageFace = 4;         // the moments blur's least face
uint64_t budget_texels(const CaseConfig& config);  // --shadow-budget, or the uniform atlas's texels
std::vector<int> face_sizes(const CaseConfig& config, const scene::Scene& scene, int frame = 0);
// The case's atlas as allocated (layout atlas; `scene` holds at least light_count point lights): the lights'
// face_sizes at frame 0 packed. With re-plans (CaseConfig::atlas_replan_frames) the texture must hold every
// later plan, so it keeps a rectangle: by_distance the uniform atlas's (no tile is larger than --cube), and
// by_coverage frame 0's within the budget (each re-plan takes the largest scale that fits it, and fills
// what it leaves); frame 0's tiles are packed into it.
Plan plan_for(const CaseConfig& config, const scene::Scene& scene);
// Re-plans (backends/common/atlas_replan.cpp). The tiles in force at `frame`: plan_for's without re-plans;
// with them, the plan of the last re-plan frame at or before it (every atlas_replan_frames frames from 0, as
// that frame has its camera and lights), each re-plan made from the one before (replan), within the allocated
// width x height. A function of the frame alone, so that the backends and the checks that replay a frame
// agree; a light whose block changes must render again (its texels are elsewhere).
Plan plan_at(const CaseConfig& config, const scene::Scene& scene, int frame);
// The frame whose plan is in force at `frame` (0 without re-plans).
int planned_frame(const CaseConfig& config, int frame);
// The plan of planned frame `at` for a reader that holds `current`, planned at `current_at`: the next re-plan
// from it where `at` is the next one (stepping the chain), else plan_at's walk from frame 0.
Plan plan_after(const CaseConfig& config, const scene::Scene& scene, int at, const Plan& current,
                int current_at);
// Per light, 1 where its block differs between two plans of the same lights (it must render again).
std::vector<uint8_t> moved_blocks(const Plan& was, const Plan& now);
// The re-plan at `frame` after `before`: the sizes that frame asks for within before's width x height
// (face_sizes_within, holding before's sizes with hysteresis); every block whose size is unchanged stays
// where it was, and the others go into the space left (largest first, each at the lowest, then leftmost,
// corner of the blocks placed that holds it), so that only the lights whose size changed render again. Where
// they do not all fit, everything is packed afresh (pack_frame).
Plan replan(const CaseConfig& config, const scene::Scene& scene, int frame, const Plan& before);
// Every block at its sizes for `frame` packed afresh into a width x height atlas (plan_for's frame 0 with
// re-plans). Throws std::logic_error where they do not fit: the kept rectangle always holds them (a packing
// bug, not a case to go on with).
Plan pack_frame(const CaseConfig& config, const scene::Scene& scene, int frame, int width, int height);
// Blocks of `sizes` into before's atlas, keeping each block whose size is unchanged; none where one does not
// fit.
std::optional<Plan> place_keeping(const Plan& before, std::span<const int> sizes);
// The sizes at `frame`: face_sizes's, by_coverage's scale the largest whose fresh packing fits width x
// height, and then, lights one at a time in the order the scale rising on would reach their next size, each
// doubled where the atlas still holds it (the kept rectangle does not shrink to the sizes as frame 0's atlas
// does, and a quarter step of the scale can leave most of it empty). `held`: each light's size before a
// re-plan, which it keeps with CaseConfig::atlas_hysteresis_octaves H > 0 while the rule gives that size for
// a need (distance or coverage) within a factor 2^H of its own at `frame`, so that a lamp near a size's edge,
// or a coverage scale's step, does not resize it back and forth (each resize a whole render); empty, or H =
// 0: the rule's sizes for `frame` alone.
std::vector<int> face_sizes_within(const CaseConfig& config, const scene::Scene& scene, int frame, int width,
                                   int height, std::span<const int> held = {});

// by_coverage: why no allocation fits the case's budget (every light at the smallest tiles exceeds it); empty
// when one does.
std::string budget_problem(const CaseConfig& config);
// Every light at --cube: the plan by_distance never exceeds (what a device's limit is checked against before
// a scene is loaded).
Plan uniform_plan(const CaseConfig& config);

// Why a plan does not fit a device's 2D textures of at most `max_size` texels a side (`limit`: the API's name
// for it); empty when it fits.
std::string too_large(const Plan& plan, int max_size, const std::string& limit);

}  // namespace omnishadow::atlas
