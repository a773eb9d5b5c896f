#version 450
// The moments filters' prefilter: a 5-tap binomial blur, weights (1 4 6 4 1) / 16 (a Gaussian of sigma 1 texel),
// along one face axis of the moments cube: the shadow pass's moments along s into the second cube, then back along
// t, in the timed frame between the shadow and lighting passes. Seams: a tap past a face's edge reads the adjacent
// face as on the unfolded cube (shaders/cube_texel.glsl), so a kernel crossing an edge blurs across it. Each pass
// sums its taps in a fixed order with the weights already divided by 16 (exact in binary), so no partial sum
// exceeds the largest tap: a warped moment just below the format's largest value blurs without overflowing (with
// integer weights the sum of 16 times it would be infinite). bench/truth/moments_check.cpp bounds the rounding.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#if defined(MOMENTS_RG16F)
#define MOMENTS_FORMAT rg16f
#elif defined(MOMENTS_R32F)
#define MOMENTS_FORMAT r32f
#elif defined(MOMENTS_R16F)
#define MOMENTS_FORMAT r16f
#elif defined(MOMENTS_RGBA32F)
#define MOMENTS_FORMAT rgba32f
#elif defined(MOMENTS_RGBA16F)
#define MOMENTS_FORMAT rgba16f
#else
#define MOMENTS_FORMAT rg32f
#endif

#ifdef VULKAN
layout(set = 0, binding = 0, MOMENTS_FORMAT) uniform readonly image2DArray source;  // six faces as layers
layout(set = 0, binding = 1, MOMENTS_FORMAT) uniform writeonly image2DArray target;
layout(push_constant) uniform Params { int size; int axis; int first_layer; int span; ivec2 block; } params;
#else
layout(binding = 0, MOMENTS_FORMAT) uniform readonly image2DArray source;
layout(binding = 1, MOMENTS_FORMAT) uniform writeonly image2DArray target;
layout(location = 0) uniform int u_size;
layout(location = 1) uniform int u_axis;  // 0: along s, 1: along t
layout(location = 2) uniform int u_first_layer;  // the light's first layer: its six faces follow (z = face)
layout(location = 3) uniform ivec2 u_block;       // layout atlas: the light's block's first texel
layout(location = 4) uniform int u_span;          // layout atlas: a tile with its borders (texels); 0: layers
#endif

#include "cube_texel.glsl"

// Where texel (s, t) of the light's face f is stored: layer first_layer + f, or in an atlas (span > 0) the face's
// tile of the light's block on layer 0, face f at column f % 3 and row f / 3, N texels inside a border
// (backends/common/atlas.h: atlas::face_origin, the same arithmetic).
ivec3 stored_texel(ivec3 t, int size, int first_layer, ivec2 block, int span) {
  if (span == 0) return ivec3(t.xy, first_layer + t.z);
  return ivec3(block + ivec2(t.z % 3, t.z / 3) * span + (span - size) / 2 + t.xy, 0);
}

const float kWeights[5] = float[](1.0 / 16.0, 4.0 / 16.0, 6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0);

void main() {
#ifdef VULKAN
  const int size = params.size, axis = params.axis, first_layer = params.first_layer, span = params.span;
  const ivec2 block = params.block;
#else
  const int size = u_size, axis = u_axis, first_layer = u_first_layer, span = u_span;
  const ivec2 block = u_block;
#endif
  const ivec3 id = ivec3(gl_GlobalInvocationID);  // z: the face of one light's cube
  if (id.x >= size || id.y >= size) return;
  vec4 sum = vec4(0.0);
  for (int k = -2; k <= 2; ++k)
    sum += kWeights[k + 2] * imageLoad(source, stored_texel(neighbour_texel(id.z, id.x, id.y, axis, k, size), size,
                                                            first_layer, block, span));
  imageStore(target, stored_texel(id, size, first_layer, block, span), sum);
}
