// The moments filters' two halves, one place for both APIs: what the shadow pass stores (STORAGE_*_MOMENTS, of
// z = distance / far in [0, 1], the depth the same fragment writes) and how the lighting pass turns the blurred,
// bilinearly filtered moments back into a shadow (FILTER_*). bench/truth/moments_check.cpp holds the stored
// moments' C++ form, which checks what the device stored.

#if defined(STORAGE_VSM_MOMENTS)
#define MOMENTS_STORAGE
vec4 distance_moments(float z) { return vec4(z, z * z, 0.0, 0.0); }
#elif defined(STORAGE_ESM_EXP)
#define MOMENTS_STORAGE
// z clamped to 1 as the depth is (a face corner is sqrt(3) x far away), so exp(c z) <= exp(c) stays finite.
vec4 distance_moments(float z) { return vec4(exp(frame.knobs.w * min(z, 1.0)), 0.0, 0.0, 0.0); }
#endif

#if defined(FILTER_VSM)
// Chebyshev's one-sided bound (Donnelly & Lauritzen 2006): with mean m1 and variance m2 - m1^2 of the occluders'
// z over the filter's footprint, the fraction at or beyond t > m1 is at most var / (var + (t - m1)^2); that bound
// is the lit fraction. The variance is floored at frame.knobs.w (4 ulps of the moments' format at z = 1:
// below it m2 - m1^2 is rounding, and a flat surface would shadow itself). t is the receiver's z less the bias.
float vsm_shadow(vec3 dir, float current, float bias) {
  vec2 m = texture(shadow_map, dir).rg;
  float t = (current - bias) / light_far();
  if (t <= m.x) return 0.0;
  float variance = max(m.y - m.x * m.x, frame.knobs.w);
  float d = t - m.x;
  return 1.0 - variance / (variance + d * d);
}
#endif

#if defined(FILTER_ESM)
// Annen et al. 2008: with occluders at or before the receiver, the filtered exp(c z_occ) times exp(-c t) is at
// most 1 where lit and falls off exponentially behind an occluder; clamped to [0, 1] it is the lit fraction.
// c = frame.knobs.w; the product is formed as exp(log(m) - c t) so that neither factor overflows.
float esm_shadow(vec3 dir, float current, float bias) {
  float m = texture(shadow_map, dir).r;
  float t = (current - bias) / light_far();
  return 1.0 - clamp(exp(log(max(m, 1e-30)) - frame.knobs.w * t), 0.0, 1.0);
}
#endif
