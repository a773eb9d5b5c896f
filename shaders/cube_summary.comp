#version 450
// The cube's check data without reading the cube back: per face a 64-bit hash of the stored values and the count
// of non-finite ones, and the texels of the check grid (backends/backend.h CubeSummary). Two faces with equal
// hashes hold the same values, so the checks compare hashes first and read a cube back in full only when they
// differ. Values are hashed as stored (depth or R32F, as texelFetch returns them), so hashes compare between cases
// of one backend and storage, never across APIs.
//
// Hash: per texel, two different bijective 32-bit mixes of (value bits, texel index) summed modulo 2^32. One texel
// changed always changes both sums (each mix is a bijection of the value for a given index); several changes
// cancel in both only by chance (about 2^-64). Sums do not depend on the order the invocations run in.
layout(local_size_x = 16, local_size_y = 16, local_size_z = 1) in;

#ifdef VULKAN
layout(set = 0, binding = 0) uniform sampler2DArray cube_layers;  // the cube's six faces as layers, face order
layout(push_constant) uniform Params { int size; int stride; } params;
#else
layout(binding = 0) uniform sampler2DArray cube_layers;
layout(location = 0) uniform int u_size;
layout(location = 1) uniform int u_stride;
#endif

// words[f] and words[6 + f]: face f's two hash halves; words[12 + f]: its non-finite count; sample: per face,
// (size / stride)^2 values, row-major, texel (x * stride + stride / 2, y * stride + stride / 2).
layout(std430, binding = 1) buffer Summary {
  uint words[24];
  float sample_values[];
} summary;

shared uint group_low, group_high, group_non_finite;

uint mix_low(uint v, uint i) {
  uint x = v ^ (i * 0x9E3779B9u);
  x ^= x >> 16; x *= 0x85EBCA6Bu; x ^= x >> 13; x *= 0xC2B2AE35u; x ^= x >> 16;
  return x;
}

uint mix_high(uint v, uint i) {
  uint x = v + (i * 0x632BE5ABu) + 0x5BD1E995u;
  x ^= x >> 15; x *= 0x2C1B3C6Du; x ^= x >> 12; x *= 0x297A2D39u; x ^= x >> 15;
  return x;
}

// Each invocation walks kRows texels down a column (neighbours read neighbouring texels of a row) and sums in
// registers: three shared atomics per invocation, not per texel (llvmpipe runs atomics slowly; GPUs gain too).
const int kRows = 16;

void main() {
#ifdef VULKAN
  const int size = params.size, stride = params.stride;
#else
  const int size = u_size, stride = u_stride;
#endif
  const int face = int(gl_GlobalInvocationID.z);
  if (gl_LocalInvocationIndex == 0u) {
    group_low = 0u;
    group_high = 0u;
    group_non_finite = 0u;
  }
  barrier();
  const int x = int(gl_GlobalInvocationID.x), first_row = int(gl_GlobalInvocationID.y) * kRows;
  const int grid = size / stride;
  uint low = 0u, high = 0u, non_finite = 0u;
  for (int y = first_row; y < min(first_row + kRows, size) && x < size; ++y) {
    const float value = texelFetch(cube_layers, ivec3(x, y, face), 0).r;
    const uint texel_index = uint(y * size + x);
    low += mix_low(floatBitsToUint(value), texel_index);
    high += mix_high(floatBitsToUint(value), texel_index);
    if (isnan(value) || isinf(value)) ++non_finite;
    const ivec2 cell = ivec2(x, y) / stride;
    if (x % stride == stride / 2 && y % stride == stride / 2 && cell.x < grid && cell.y < grid)
      summary.sample_values[(face * grid + cell.y) * grid + cell.x] = value;
  }
  atomicAdd(group_low, low);
  atomicAdd(group_high, high);
  atomicAdd(group_non_finite, non_finite);
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    atomicAdd(summary.words[face], group_low);
    atomicAdd(summary.words[6 + face], group_high);
    atomicAdd(summary.words[12 + face], group_non_finite);
  }
}
