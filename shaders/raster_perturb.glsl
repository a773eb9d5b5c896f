// Test only (--raster-perturb, CaseConfig::raster_perturb_steps): moves a shadow- or map-pass vertex in window
// space by up to kRasterPerturbNdc (the requested sub-pixel steps as NDC units of the target), in a direction
// hashed from its world position, so that vertices shared by triangles move alike and meshes stay closed. In every
// real run the constant is 0 and the compiler folds perturb_raster() to its argument: the timed pass is unchanged.
// Vulkan sets it as a specialisation constant of the vertex and geometry stages; GL compiles it as a #define.
#ifdef VULKAN
layout(constant_id = 0) const float kRasterPerturbNdc = 0.0;
#elif defined(RASTER_PERTURB_NDC)
const float kRasterPerturbNdc = RASTER_PERTURB_NDC;
#else
const float kRasterPerturbNdc = 0.0;
#endif

// A direction in [-1, 1]^2 from the position's bits (a 32-bit integer hash; deterministic on every device).
vec2 raster_perturbation(vec3 world) {
  uvec3 u = floatBitsToUint(world);
  uint h = (u.x * 0x9E3779B1u) ^ (u.y * 0x85EBCA77u) ^ (u.z * 0xC2B2AE3Du);
  h ^= h >> 15u;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12u;
  h *= 0x297A2D39u;
  h ^= h >> 15u;
  return vec2(float(h & 0xFFFFu), float(h >> 16u)) / 65535.0 * 2.0 - 1.0;
}

vec4 perturb_raster(vec4 clip, vec3 world) {
  if (kRasterPerturbNdc == 0.0) return clip;
  clip.xy += raster_perturbation(world) * kRasterPerturbNdc * clip.w;  // window offset = NDC offset, after the divide
  return clip;
}
