#pragma once
// The render targets of one case: the shadow cube (per storage) with its framebuffers, and the lighting
// framebuffer (lit colour, shadow factor, world position). Created by configure(), owned by GlBackend.

#include <epoxy/gl.h>

#include <optional>
#include <vector>

#include "backends/common/atlas.h"
#include "backends/common/case_config.h"

namespace omnishadow::gl {

struct ShadowTargets {
  GLuint depth = 0;    // the depth cube the pass tests against
  GLuint colour = 0;   // the colour cube beside it: R32F distances (r32f_distance) or moments; 0 for neither
  GLuint stored = 0;   // what the checks read: the depth cube, or the colour one for r32f_distance
  GLuint sampled = 0;  // what the lighting pass samples: `stored`, or the moments cube
  // Multiview (GL_OVR_multiview2) renders into 2D array textures, never cube maps: the cube is then a texture
  // view (GL 4.3) of six array layers, sampled and read back as the cube. 0 for every other technique.
  GLuint depth_array = 0, colour_array = 0, stored_array = 0;
  // The stored cube as a 2D array (a texture view of it, or stored_array itself): what the cube summary's
  // compute shader fetches texels from (a cube sampler has no texelFetch).
  GLuint stored_layers = 0;
  // Moments storages: the moments cube as a 2D array (image units bind layers), the blur's intermediate (six
  // layers) and their internal format; 0 otherwise.
  GLuint colour_layers = 0, blur_layers = 0;
  GLenum colour_format = 0;
  // What the lighting pass samples for layout face_array: `sampled` as a 2D array (stored_layers, or
  // colour_layers for moments); views, not copies, so both layouts read the very texels the shadow pass
  // wrote.
  GLuint sampled_layers = 0;
  int layers = 6;  // per light: 6 for a cube's faces; a layout of other layers (dual_paraboloid: 2) is a
                   // plain 2D array, with no cube view: depth == depth_array, colour == colour_array
  // Point lights: light k's layers are layers k * `layers` .. (k + 1) * `layers` - 1 of the arrays. Several
  // lights, or layout cube_array, are always rendered into 2D arrays; `depth` and `colour` are then a
  // cube-map-array view of them (cube_array) or the arrays themselves.
  int lights = 1;
  std::vector<GLuint> face_fbos;  // six_pass: one framebuffer per light and layer (light-major), built once
  std::vector<GLuint> layered_fbos;  // single-pass techniques: one per light over its layers, gl_Layer (or
                                     // the view) picks the face
  // Every light in one pass (LightGrouping::all_lights): one layered framebuffer over every light's layers
  // (layered_fbos[0] itself for one light).
  GLuint all_lights_fbo = 0;
  // Per light: its stored layers as a 2D array (the summary's input).
  std::vector<GLuint> light_stored_layers;
  std::vector<GLuint> views;  // per-light views made for the above, deleted with the targets
  Storage storage = Storage::linear_depth;
  int size = 0;
  // Layout atlas: every light's faces are tiles of layer 0 of depth_array (and colour_array), rendered
  // through layered_fbos[0] with a viewport per face (backends/common/atlas.h); face_fbos stay empty.
  std::optional<atlas::Plan> atlas;
  // Layout cube with several lights: light k's six layers of what the lighting pass samples, as a cube map
  // (a texture view, GL 4.3), each bound to a unit of its own; empty otherwise.
  std::vector<GLuint> light_cubes;
};

// What create_shadow_targets() builds: one map of `layers` layers of size^2 per light.
struct ShadowShape {
  int size = 0;
  Storage storage = Storage::linear_depth;
  DepthFormat depth_format = DepthFormat::d32f;
  bool multiview = false;  // GL_OVR_multiview2 renders into 2D arrays, never cube maps
  int layers = 6;          // per light
  int lights = 1;
  bool cube_array = false;           // sampled as a cube-map array (layout cube_array)
  std::optional<atlas::Plan> atlas;  // layout atlas: one layer of the plan's size holds every light's faces
  bool light_cubes = false;          // layout cube with several lights: a cube view per light (light_cubes)
};

// Spot/directional lights: a 2D depth-array texture, one layer and one framebuffer per light. At least one
// layer always exists so the lighting program's sampler has a texture even when the scene has no such light.
struct MapTargets {
  GLuint depth = 0;
  std::vector<GLuint> fbos;
  int size = 0;
};
MapTargets create_map_targets(int size, int layers, DepthFormat depth_format);
void destroy(MapTargets& t);

// The timed variant has the colour and depth only; the check variant adds the shadow factor and world
// position.
struct LightingTargets {
  GLuint fbo = 0;
  GLuint color = 0;          // RGBA8 lit frame
  GLuint shadow_factor = 0;  // R32F (check variant)
  GLuint position = 0;       // RGBA32F world position, w = 1 where covered (check variant)
  GLuint depth = 0;          // D32F renderbuffer
  int width = 0;
  int height = 0;
};

GLenum depth_internal_format(DepthFormat format);
// Throw std::runtime_error naming the incomplete framebuffer, or GL_OUT_OF_MEMORY for allocations that
// failed. multiview: the layered framebuffer holds six views of the arrays
// (glFramebufferTextureMultiviewOVR).
ShadowTargets create_shadow_targets(const ShadowShape& shape);
void destroy(ShadowTargets& t);
LightingTargets create_lighting_targets(int width, int height, bool check_outputs);
void destroy(LightingTargets& t);

}  // namespace omnishadow::gl
