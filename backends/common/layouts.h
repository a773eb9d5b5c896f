#pragma once
// A layout is how a point light's depth is stored and looked up: N layers, a texel <-> direction
// map, a projection per layer and the lookup that picks the layer. One row per layout; the spellings (CLI,
// case ids, JSON), the shader-variant list and both backends read it. Adding a layout: a Layout value, a row
// here, its lookup in shaders/shadow_filters.glsl under its define, and each backend's storage for it.

#include <array>
#include <string_view>

#include "backends/common/case_config.h"

namespace omnishadow {

// How a layer's texels map to directions from the light, which the texel truths and the read-back walk.
enum class TexelMap {
  cube_faces,   // layer f is cube face f (face order and up vectors in cube_faces.h), texel <-> direction by
                // the cube-map rule (GL 4.5 table 8.19): the cube's own map
  paraboloid,   // layer 0 the hemisphere z >= 0, layer 1 z < 0, each a paraboloid
                // (backends/common/paraboloid.h)
  tetrahedral,  // layer f a perspective face along a tetrahedron vertex (backends/common/tetrahedron.h)
};

// How the lighting pass turns a direction into a stored value.
enum class LayoutLookup {
  hardware_cube,  // samplerCube: the sampler selects the face; LINEAR filtering crosses seams (Vulkan's cubes
                  // are seamless; the GL backend enables GL_TEXTURE_CUBE_MAP_SEAMLESS)
  shader_face,  // sampler2DArray: the shader selects layer and (s, t) by the same rule; filtering clamps per
                // face
  shader_paraboloid,   // sampler2DArray: the shader selects the hemisphere's layer and its paraboloid point
  shader_tetrahedral,  // sampler2DArray: the shader selects the nearest face axis and projects onto that face
};

struct LayoutTraits {
  Layout layout;
  std::string_view name;             // CLI, case ids, JSON
  std::string_view lighting_define;  // shadow_filters.glsl's variant; empty for the cube (the default source)
  int layers;                        // layers of the stored image
  TexelMap texel_map;
  LayoutLookup lookup;
};

inline constexpr std::array<LayoutTraits, 4> kLayouts = {{
    {Layout::cube, "cube", "", 6, TexelMap::cube_faces, LayoutLookup::hardware_cube},
    {Layout::face_array, "face_array", "LAYOUT_FACE_ARRAY", 6, TexelMap::cube_faces,
     LayoutLookup::shader_face},
    {Layout::dual_paraboloid, "dual_paraboloid", "LAYOUT_DUAL_PARABOLOID", 2, TexelMap::paraboloid,
     LayoutLookup::shader_paraboloid},
    {Layout::tetrahedral, "tetrahedral", "LAYOUT_TETRAHEDRAL", 4, TexelMap::tetrahedral,
     LayoutLookup::shader_tetrahedral},
}};

constexpr const LayoutTraits& traits(Layout l) {
  for (const LayoutTraits& row : kLayouts)
    if (row.layout == l) return row;
  return kLayouts[0];  // unreachable: every Layout has a row (checked below)
}
constexpr bool every_layout_has_its_row() {
  for (size_t i = 0; i < kLayouts.size(); ++i)
    if (static_cast<size_t>(kLayouts[i].layout) != i) return false;
  return true;
}
static_assert(every_layout_has_its_row(), "kLayouts lists the layouts in enum order");

// A layer's edge in texels for `--cube N`: the size axis is memory, so every layout stores about 6 N^2 texels
// (the equal-memory comparison): a cube face N, a paraboloid layer round(N sqrt 3), a
// tetrahedron's face round(N sqrt 1.5).
int layer_size(Layout layout, int cube_size);

}  // namespace omnishadow
