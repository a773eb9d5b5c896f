// The moments filters' two halves, one place for both APIs: what the shadow pass stores (STORAGE_*_MOMENTS, of
// z = distance / far in [0, 1], the depth the same fragment writes) and how the lighting pass turns the blurred,
// bilinearly filtered moments back into a shadow (FILTER_*). bench/truth/moments_check.cpp holds the stored
// moments' C++ form, which checks what the device stored.

#if defined(STORAGE_VSM_MOMENTS)
#define MOMENTS_STORAGE
// moments_distance_scale() = 1, or far for the world-units variant (MomentsTuning::world_units).
vec4 distance_moments(float z) {
  float d = z * moments_distance_scale();
  return vec4(d, d * d, 0.0, 0.0);
}
#elif defined(STORAGE_ESM_EXP)
#define MOMENTS_STORAGE
// z clamped to 1 as the depth is (a face corner is sqrt(3) x far away), so exp(c z) <= exp(c) stays finite.
vec4 distance_moments(float z) { return vec4(exp(frame.knobs.w * min(z, 1.0)), 0.0, 0.0, 0.0); }
#elif defined(STORAGE_MSM_MOMENTS)
#define MOMENTS_STORAGE
vec4 distance_moments(float z) {
  float c = min(z, 1.0), c2 = c * c;
  return vec4(c, c2, c2 * c, c2 * c2);
}
#elif defined(STORAGE_EVSM2_MOMENTS) || defined(STORAGE_EVSM4_MOMENTS)
#define MOMENTS_STORAGE
// Both warps of min(z, 1) with c = frame.knobs.w (e^(2c) finite in the format); a 2-channel cube keeps the first two.
vec4 distance_moments(float z) {
  float p = exp(frame.knobs.w * min(z, 1.0)), n = exp(-frame.knobs.w * min(z, 1.0));
  return vec4(p, p * p, -n, n * n);
}
#endif

#if defined(FILTER_VSM) || defined(FILTER_EVSM2) || defined(FILTER_EVSM4) || defined(FILTER_MSM)
// Light-bleeding reduction (MomentsTuning::bleed_reduction, frame.moments_knobs.x = a): an upper bound p on the lit
// fraction below a is taken as shadow, the rest rescaled to [0, 1]. a = 0 returns p unchanged (p / 1 is exact).
float reduce_bleeding(float lit) {
  float a = frame.moments_knobs.x;
  return clamp((lit - a) / (1.0 - a), 0.0, 1.0);
}
#endif

#if defined(FILTER_VSM)
// Chebyshev's one-sided bound (Donnelly & Lauritzen 2006): with mean m1 and variance m2 - m1^2 of the occluders'
// z over the filter's footprint, the fraction at or beyond t > m1 is at most var / (var + (t - m1)^2); that bound
// is the lit fraction. The variance is floored at frame.knobs.w x m2 (4 units of the moments' format's rounding of
// m2: below it m2 - m1^2 is rounding, and a flat surface would shadow itself). Relative to m2, the floor holds for
// any range of z and any units (a floor fixed at z = 1 blurs a scene that spans z < 0.1 by 100 times too much at
// 16 bits). t is the receiver's z less the bias, in the stored moments' units (times far in world units).
float vsm_shadow(vec3 dir, float current, float bias) {
  vec2 m = texture(shadow_map, shadow_coord(dir)).rg;
  float t = (current - bias) / light_far() * moments_distance_scale();
  if (t <= m.x) return 0.0;
  float variance = max(m.y - m.x * m.x, frame.knobs.w * m.y);
  float d = t - m.x;
  return 1.0 - reduce_bleeding(variance / (variance + d * d));
}
#endif

#if defined(FILTER_EVSM2) || defined(FILTER_EVSM4)
// Chebyshev's one-sided bound on warped moments (mean, mean of squares) at the warped receiver w, with the variance
// floored at 4 units of the format's rounding of w^2 (unit = frame.moments_knobs.z: 2^-24 float, 2^-11 half; the
// warp spreads z, so the floor scales with w^2 rather than being one constant).
float chebyshev_lit(vec2 m, float w, float unit) {
  if (w <= m.x) return 1.0;
  float variance = max(m.y - m.x * m.x, 4.0 * unit * w * w);
  float d = w - m.x;
  return variance / (variance + d * d);
}

// Lauritzen & McCool 2008: VSM on e^(cz) (and, evsm4, on -e^(-cz)), the lesser bound.
float evsm_shadow(vec3 dir, float current, float bias) {
  vec4 m = texture(shadow_map, shadow_coord(dir));
  float c = frame.knobs.w, t = min((current - bias) / light_far(), 1.0);
  float unit = frame.moments_knobs.z;
  float lit = chebyshev_lit(m.xy, exp(c * t), unit);
#if defined(FILTER_EVSM4)
  lit = min(lit, chebyshev_lit(m.zw, -exp(-c * t), unit));
#endif
  return 1.0 - reduce_bleeding(lit);
}
#endif

#if defined(FILTER_MSM)
// Hamburger 4MSM (Peters & Klein 2015). The biased moments b are those of some distribution of occluder depths on
// [0, 1]; the receiver at t is shadowed at least by the sharpest such bound, reached by a distribution on three
// points: t and the two roots z2 < z3 of c3 x^2 + c2 x + c1, where c solves the Hankel system
// [1 b1 b2; b1 b2 b3; b2 b3 b4] c = (1, t, t^2) (by its LDL^T factorisation). Bias alpha = frame.knobs.w.
float msm_shadow(vec3 dir, float current, float bias) {
  vec4 b = mix(texture(shadow_map, shadow_coord(dir)), vec4(0.5), frame.knobs.w);
  float t = min((current - bias) / light_far(), 1.0);
  float d22 = b.y - b.x * b.x;
  float l32 = (b.z - b.x * b.y) / d22;
  float d33 = b.w - b.y * b.y - l32 * l32 * d22;
  float y2 = (t - b.x) / d22;
  float y3 = (t * t - b.y - l32 * (t - b.x)) / d33;
  float c3 = y3, c2 = y2 - l32 * c3, c1 = 1.0 - b.x * c2 - b.y * c3;
  float p = c2 / c3, q = c1 / c3;
  float r = sqrt(max(p * p * 0.25 - q, 0.0));
  float z2 = -0.5 * p - r, z3 = -0.5 * p + r;
  if (t <= z2) return 0.0;
  float shadow = t <= z3 ? (t * z3 - b.x * (t + z3) + b.y) / ((z3 - z2) * (t - z2))
                         : 1.0 - (z2 * z3 - b.x * (z2 + z3) + b.y) / ((t - z2) * (t - z3));
  return 1.0 - reduce_bleeding(1.0 - clamp(shadow, 0.0, 1.0));
}
#endif

#if defined(FILTER_ESM)
// Annen et al. 2008: with occluders at or before the receiver, the filtered exp(c z_occ) times exp(-c t) is at
// most 1 where lit and falls off exponentially behind an occluder; clamped to [0, 1] it is the lit fraction.
// c = frame.knobs.w; the product is formed as exp(log(m) - c t) so that neither factor overflows.
float esm_shadow(vec3 dir, float current, float bias) {
  float m = texture(shadow_map, shadow_coord(dir)).r;
  float t = (current - bias) / light_far();
  return 1.0 - clamp(exp(log(max(m, 1e-30)) - frame.knobs.w * t), 0.0, 1.0);
}
#endif
