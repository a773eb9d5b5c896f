#pragma once
// Shadow error against exact visibility. The truth is computed per pixel from the world positions the GPU
// rendered, by casting rays against the scene's own triangles (backends/reference): a point light's exact
// visibility, and the fractional visibility of a spherical light of a stated radius (stratified samples),
// which is the penumbra that PCF imitates.

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "backends/backend.h"
#include "backends/reference/ray_caster.h"

namespace omnishadow::bench {

struct TruthOptions {
  float light_radius = 0.1f;  // world units; 0 = point light only
  int samples_per_axis = 8;   // stratified samples on the light's disk: 8 x 8 = 64
  // The soft reference (samples_per_axis^2 rays a pixel) is cast at every sphere_stride-th pixel in x and y;
  // 0 = automatic: every pixel up to kSphereFullPixels, above that the smallest stride that brings it under
  // them (1920x1080: 3, 3840x2160: 5). mae_sphere and psnr_sphere are means, which a regular subsample
  // estimates; the misclassified and point-light figures use every pixel.
  int sphere_stride = 0;
};
inline constexpr int kSphereFullPixels = 800 * 600;
int sphere_stride_for(const TruthOptions& options, int width, int height);

// Which light does a filter imitate? The soft reference's radius is one arbitrary choice, so every case is
// also compared with spherical lights of these radii (world units; 0 = the point light) and reports the
// radius whose shadow it matches best (least mean |difference|). Sampled sparsely to stay cheap next to the
// main reference: every kFitStride-th pixel in x and y, kFitSamplesPerAxis^2 stratified rays per pixel and
// radius.
inline constexpr std::array<float, 8> kFitRadii = {0.0f, 0.025f, 0.05f, 0.1f, 0.2f, 0.4f, 0.8f, 1.6f};
inline constexpr int kFitStride = 4;
inline int fit_stride_for(int sphere_stride) { return kFitStride * sphere_stride; }
inline constexpr int kFitSamplesPerAxis = 4;

struct Truth {
  int width = 0, height = 0;
  TruthOptions options;
  std::vector<uint8_t> covered;      // 1 where the GPU drew a surface
  std::vector<float> point_shadow;   // 1 = the point light is hidden, 0 = visible
  std::vector<float> sphere_shadow;  // hidden fraction of the spherical light (empty when radius is 0); only
  int sphere_stride = 1;             // pixels with x and y multiples of sphere_stride hold it
  std::vector<glm::vec3> direct;     // unshadowed (diffuse + specular) * albedo, from the exact surface hit
  std::vector<uint8_t> has_direct;   // 0 where the camera ray found no surface at the GPU's position
  // The radius fit (empty without a soft reference, or for spot/directional lights): the pixels sampled
  // (indices into the image) and, per kFitRadii entry, the hidden fraction of that light at each.
  std::vector<uint32_t> fit_pixels;
  std::vector<std::vector<float>> fit_shadow;
  uint64_t reused_pixels = 0;  // covered pixels taken from a TruthPrior instead of cast again
};

// A truth already cast for other images of the same scene, frame, size and options (another API's, another
// technique's lighting pass), with the world positions it was cast from. A pixel whose position here stands
// for the same surface point (same_surface_point) takes its values instead of casting again: one truth per
// scene for both APIs, whose interpolated positions differ in the last bits (llvmpipe against lavapipe, heavy
// 400x300: 1.4% of pixels bitwise equal, the largest difference 6.9e-5).
struct TruthPrior {
  const Truth* truth = nullptr;
  const std::vector<float>* positions = nullptr;  // RGBA per pixel, as Images::world_position
};

// Two GPU positions of one pixel stand for the same surface point when they differ by less than both (a) what
// the floating-point rules let two conformant implementations differ by: GL 4.5 section 2.3.4.1 asks each
// operation to be accurate to about 1 part in 1e5, and an interpolated position is about ten operations on
// values as large as |p| and the camera distance, so 1e-4 of those; and (b) a sixteenth of the pixel's
// footprint at that distance, the finest step GL's minimum of four sub-pixel bits resolves, so that a
// far-from-origin scene (where (a) grows to many pixels) never shares across pixels' worth of surface.
// Everything else (silhouettes, a triangle one API drew and the other did not) is cast again.
bool same_surface_point(const glm::vec3& a, const glm::vec3& b, const glm::vec3& camera, float pixel_angle);

Truth compute_truth(const reference::RayCaster& caster, const scene::Scene& scene, int frame,
                    const Images& images, const TruthOptions& options, const TruthPrior& prior = {});

struct Accuracy {
  uint64_t pixels = 0;               // covered pixels compared
  double misclassified_percent = 0;  // (GPU shadow factor > 0.5) != point-light truth
  double false_shadow_percent = 0;   // GPU shadowed where the light is visible (acne, over-darkening)
  double missed_shadow_percent = 0;  // GPU lit where the light is hidden (leaks, peter panning)
  double mae_point = 0;              // mean |GPU shadow factor - point-light truth|
  double mae_sphere = -1;            // mean |GPU shadow factor - spherical-light truth|; -1 without it
  double psnr_point_db = -1;   // lit frame vs the same frame lit with exact point visibility; -1 = identical
  double psnr_sphere_db = -1;  // ... with the spherical light's visibility; -1 = identical or absent
  int sphere_stride = 1;       // the two sphere figures are over every sphere_stride-th pixel in x and y
  uint64_t sphere_pixels = 0;  // covered pixels they are over
  // The radius fit: mean |GPU shadow factor - truth| per kFitRadii entry over the sampled pixels, and the
  // best.
  std::vector<double> fit_mae;
  double fit_radius = -1;  // -1 without a fit
  double fit_mae_best = -1;
};

Accuracy measure_accuracy(const Truth& truth, const Images& images);

// The lit frame's error from every light together, against the frame lit with each light's exact visibility:
// lit = base + sum_k (1 - s_k) direct_k, so a pixel's colour is off by sum_k (s_k - t_k) direct_k, where one
// light's error may cancel another's. The PSNR (peak 1) over the covered pixels every light's truth lit; -1
// when no value differs. Each pair: a light's truth and the images that report its shadow factor.
double lit_psnr_of_lights(const std::vector<std::pair<const Truth*, const Images*>>& lights);

// Top-down RGB: grey = agreement (light grey lit, dark grey shadowed), red = false shadow, blue = missed
// shadow, brightness by |difference| against the point-light truth.
std::vector<uint8_t> error_heatmap(const Truth& truth, const Images& images);

// A 64-bit fingerprint of the world positions: equal positions share one truth.
uint64_t positions_fingerprint(const Images& images);

}  // namespace omnishadow::bench
