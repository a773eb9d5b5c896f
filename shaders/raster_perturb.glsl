// Test only (--raster-perturb, CaseConfig::raster_perturb_steps): moves every shadow- and map-pass vertex in window
// space by up to kRasterPerturbNdc (the requested sub-pixel steps as NDC units of the target), as a rasteriser
// that snaps differently from this one would. In every real run the constant is 0 and the compiler folds
// perturb_raster() to its argument: the timed pass is unchanged. Vulkan sets it as a specialisation constant of the
// vertex and geometry stages; GL compiles it as a #define. The constant is one step in a --cube-sized target;
// `cube_texels` (how many --cube texels one of the target's spans) makes it a step of the target the pass draws
// into, so an atlas tile smaller than --cube moves by as many of its own steps as a cube does.
//
// The offset is a fixed linear map of clip space (NDC offset = k (a + b x_ndc + c y_ndc), |a| + |b| + |c| <= 1), a
// function of the vertex's position, so shared vertices move alike and meshes stay closed. It must be linear: the
// clipper interpolates clip coordinates, and a per-vertex offset proportional to w (a hash per vertex, say) is
// amplified at the vertices it creates on triangles that cross the light's plane (one vertex behind the light),
// moving edges by many steps where a GPU, which snaps after clipping, moves them by at most one. A linear map
// commutes with that interpolation, so every window-space point within the target moves by at most k.
#ifdef VULKAN
layout(constant_id = 0) const float kRasterPerturbNdc = 0.0;
#elif defined(RASTER_PERTURB_NDC)
const float kRasterPerturbNdc = RASTER_PERTURB_NDC;
#else
const float kRasterPerturbNdc = 0.0;
#endif

vec4 perturb_raster_in(vec4 clip, float cube_texels) {
  if (kRasterPerturbNdc == 0.0) return clip;
  // x: k (0.5 + 0.3 x + 0.2 y) in [0, k]; y: k (-0.4 + 0.25 x - 0.35 y) in [-k, 0.2 k] for |x|, |y| <= 1.
  float k = kRasterPerturbNdc * cube_texels;
  clip.x += k * (0.5 * clip.w + 0.3 * clip.x + 0.2 * clip.y);
  clip.y += k * (-0.4 * clip.w + 0.25 * clip.x - 0.35 * clip.y);
  return clip;
}

// The shadow pass: the light's layers (frame.raster_knobs.x: --cube / their edge: an atlas tile's, a layout's layer).
vec4 perturb_raster(vec4 clip) { return perturb_raster_in(clip, frame.raster_knobs.x); }
