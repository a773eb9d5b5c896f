#pragma once
// A layout is how a point light's depth is stored and looked up: N layers, a texel <-> direction
// map, a projection per layer and the lookup that picks the layer. One row per layout, carrying its geometry
// (TexelGeometry: layer count and size, texel directions, view-projections, clipping); the spellings (CLI,
// case ids, JSON), the shader variants (its define, and LAYOUT_LAYERS for the shadow pass), the texel truths,
// the frame uniforms and both backends read it. Adding a layout: a Layout value, a row here (a TexelGeometry
// for a new texel map, with its functions in layouts.cpp), its shadow-pass warp and its lookup in shaders/
// under its define, and each backend's API calls where it needs a feature (as clip distances).

#include <array>
#include <glm/glm.hpp>
#include <optional>
#include <span>
#include <string_view>

#include "backends/common/case_config.h"
#include "backends/common/cube_faces.h"
#include "backends/common/paraboloid.h"
#include "backends/common/tetrahedron.h"

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
  hardware_cube_array,  // samplerCubeArray: as hardware_cube, the light's cube chosen by the array index
  shader_face,  // sampler2DArray: the shader selects layer and (s, t) by the same rule; filtering clamps per
                // face
  shader_paraboloid,   // sampler2DArray: the shader selects the hemisphere's layer and its paraboloid point
  shader_tetrahedral,  // sampler2DArray: the shader selects the nearest face axis and projects onto that face
  shader_atlas,  // sampler2DArray of one layer: the shader selects the face by the cube-map rule, then its
                 // tile (backends/common/atlas.h), clamped to the tile's texel centres
};

// The ray through a point of a layer: its unit direction, and the factor that turns the layer's near and far
// (and a stored depth) into distances along it: 1 / the axis component of the unit direction for a
// perspective layer (near and far are axis distances), 1 where depth is radial.
struct LayerRay {
  glm::dvec3 unit;
  double depth_to_distance;
};

// What varies with a layout's texel map. Layers beyond `layers` (up to six) are unused; their frame uniforms
// hold the cube's faces.
struct TexelGeometry {
  TexelMap map;
  int layers;
  std::span<const char* const> layer_names;  // one per layer, for the texel truths' findings
  // A layer's edge for `--cube N`: the size axis is memory, so every layout stores about 6 N^2 texels.
  int (*layer_size_for_cube)(int cube_size);
  // The ray through continuous texel coordinates (s, t) of a layer of `size` (texel k's centre at k + 0.5);
  // nullopt where the layer stores nothing (beyond a paraboloid's hemisphere).
  std::optional<LayerRay> (*point_ray)(int layer, double s, double t, int size);
  // Whether texel (s, t) can be read by a lookup (inside a paraboloid's disk).
  bool (*texel_read)(int s, int t, int size);
  // Layer f's view-projection from the light (the frame uniforms' face_view_proj[f]).
  glm::mat4 (*view_projection)(int layer, const glm::vec3& light, float near_plane, float far_plane,
                               cube::DepthRange range);
  // Whether its texels are held to the exact truth: a paraboloid's straight-edged triangles are not the
  // curves the exact map draws (its error is reported, not judged).
  bool texels_exact;
  // Whether the shadow pass clips each layer to its hemisphere with a clip distance (GL_CLIP_DISTANCE0,
  // Vulkan's shaderClipDistance).
  bool clips_to_hemisphere;
};

namespace layout_geometry {
int cube_layer_size(int cube_size);
std::optional<LayerRay> cube_point_ray(int layer, double s, double t, int size);
std::optional<LayerRay> paraboloid_point_ray(int layer, double s, double t, int size);
std::optional<LayerRay> tetrahedral_point_ray(int layer, double s, double t, int size);
bool every_texel(int s, int t, int size);
glm::mat4 cube_view_projection(int layer, const glm::vec3& light, float near_plane, float far_plane,
                               cube::DepthRange range);
}  // namespace layout_geometry

inline constexpr TexelGeometry kCubeFaceGeometry{TexelMap::cube_faces,
                                                 6,
                                                 cube::kFaceNames,
                                                 &layout_geometry::cube_layer_size,
                                                 &layout_geometry::cube_point_ray,
                                                 &layout_geometry::every_texel,
                                                 &layout_geometry::cube_view_projection,
                                                 true,
                                                 false};
inline constexpr TexelGeometry kParaboloidGeometry{
    TexelMap::paraboloid,
    2,
    paraboloid::kLayerNames,
    &paraboloid::layer_size_for_cube,
    &layout_geometry::paraboloid_point_ray,
    &paraboloid::texel_in_disk,
    &layout_geometry::cube_view_projection,  // unused: the vertex stage warps (shaders/paraboloid.glsl)
    false,
    true};
inline constexpr TexelGeometry kTetrahedralGeometry{
    TexelMap::tetrahedral,
    4,
    tetra::kFaceNames,
    &tetra::layer_size_for_cube,
    &layout_geometry::tetrahedral_point_ray,
    &layout_geometry::every_texel,
    &tetra::face_view_projection,  // its four faces' own frusta
    true,
    false};

struct LayoutTraits {
  Layout layout;
  std::string_view name;             // CLI, case ids, JSON
  std::string_view lighting_define;  // shadow_filters.glsl's variant; empty for the cube (the default source)
  LayoutLookup lookup;
  const TexelGeometry& geometry;
};

inline constexpr std::array<LayoutTraits, 6> kLayouts = {{
    {Layout::cube, "cube", "", LayoutLookup::hardware_cube, kCubeFaceGeometry},
    {Layout::face_array, "face_array", "LAYOUT_FACE_ARRAY", LayoutLookup::shader_face, kCubeFaceGeometry},
    {Layout::dual_paraboloid, "dual_paraboloid", "LAYOUT_DUAL_PARABOLOID", LayoutLookup::shader_paraboloid,
     kParaboloidGeometry},
    {Layout::tetrahedral, "tetrahedral", "LAYOUT_TETRAHEDRAL", LayoutLookup::shader_tetrahedral,
     kTetrahedralGeometry},
    {Layout::cube_array, "cube_array", "LAYOUT_CUBE_ARRAY", LayoutLookup::hardware_cube_array,
     kCubeFaceGeometry},
    {Layout::atlas, "atlas", "LAYOUT_ATLAS", LayoutLookup::shader_atlas, kCubeFaceGeometry},
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

// Whether the shadow pass routes a face by its viewport (a tile of one layer) rather than by its layer.
constexpr bool faces_by_viewport(Layout l) { return traits(l).lookup == LayoutLookup::shader_atlas; }

// Layout cube with several point lights: one cube, and one samplerCube, per light, the lighting pass's array
// of them indexed by the light (dynamically uniform: the loop over every light). The fragment stage then
// samples kLightCubes + 1 textures; GL (GL_MAX_TEXTURE_IMAGE_UNITS) and Vulkan
// (maxPerStageDescriptorSamplers) guarantee 16, so a device at that minimum refuses it with the reason.
inline constexpr int kLightCubes = 16;

// A layer's edge in texels for `--cube N` (TexelGeometry::layer_size_for_cube): a cube face N, a paraboloid
// layer round(N sqrt 3), a tetrahedron's face round(N sqrt 1.5).
inline int layer_size(Layout layout, int cube_size) {
  return traits(layout).geometry.layer_size_for_cube(cube_size);
}

}  // namespace omnishadow
