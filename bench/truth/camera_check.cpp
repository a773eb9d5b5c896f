// The frame's camera, held independently of the matrices the backends build (frame_uniforms.cpp): every
// covered pixel's world position, read back from the lighting pass, projected through the camera the check
// frame has (scene::Camera::at) lands in that pixel. A wrong camera (another frame's place on its path, a
// swapped aspect, a flipped row order) moves most pixels by many pixels; nothing else holds the lit frame to
// where it was seen from, since every truth starts from the read-back positions.

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "bench/truth/case_checks.h"

namespace omnishadow::bench {

// Tolerance, per axis in pixels: half a pixel, plus the float rounding of positions far from the origin.
// - A one-sample pixel's fragment is sampled at its centre (GL 4.5 section 14.6, Vulkan's standard sample
//   location (0.5, 0.5)), and the position is interpolated there: it projects back to the centre up to the
//   vertices' snapping to the subpixel grid (at least 4 bits on both APIs: 1/16 pixel), far inside half a
//   pixel.
// - The position and the GPU's own vertex transform are float: the transform's four multiply-adds, the
//   matrix entries' own rounding on the host and the interpolation each round by a few units in the last
//   place of the largest coordinate in play (the point's or the camera's); 16 ulps are allowed, twice their
//   sum. A world error e at view depth z moves the projection by at most 2 e / (z * world units per pixel at
//   unit depth) pixels (the off-axis term is bounded by the frustum's tangent). Negligible at the bundled
//   scenes' 10-60 units (correct frames miss by 0.002 pixels at most); 300 pixels and more at offset_1e6 (a
//   scene 1e6 units from the origin loaded without the rebase remedy), whose frames miss by up to 110.
void check_camera(CaseFindings& r, const Images& images, const CheckContext& ctx) {
  const int w = images.width, h = images.height;
  const std::vector<float>& p = images.world_position;
  if (w < 1 || h < 1 || p.size() < 4 * size_t(w) * size_t(h)) return;
  const scene::Camera cam = ctx.scene.camera.at(ctx.options.check_frame);
  const double tan_half = std::tan(glm::radians(double(cam.fov_y_degrees)) * 0.5);
  const glm::dmat4 view = glm::lookAtRH(glm::dvec3(cam.position), glm::dvec3(cam.target), glm::dvec3(cam.up));
  const glm::dmat4 view_proj =
      glm::perspectiveRH_NO(glm::radians(double(cam.fov_y_degrees)), double(w) / double(h),
                            double(cam.near_plane), double(cam.far_plane)) *
      view;
  const double unit_pixel = 2.0 * tan_half / double(h);  // world units per pixel at view depth 1
  const double camera_extent = double(glm::length(cam.position)) + 1.0;
  uint64_t off = 0, covered = 0;
  double worst = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = 4 * (size_t(y) * size_t(w) + size_t(x));
      if (p[i + 3] != 1.0f) continue;  // nothing drawn here
      ++covered;
      const glm::dvec4 world(p[i], p[i + 1], p[i + 2], 1.0);
      const glm::dvec4 clip = view_proj * world;
      const double depth = -(view * world).z;
      const double extent =
          std::max({std::fabs(world.x), std::fabs(world.y), std::fabs(world.z), camera_extent});
      const double rounding = 16.0 * std::ldexp(extent, -23);
      const double slack = depth > 0.0 ? 2.0 * rounding / (depth * unit_pixel) : INFINITY;
      // Row 0 first in memory at clip y = -1, both APIs (backends/common/cube_faces.h).
      const double px = (clip.x / clip.w + 1.0) * 0.5 * double(w) - (double(x) + 0.5);
      const double py = (clip.y / clip.w + 1.0) * 0.5 * double(h) - (double(y) + 0.5);
      const double miss = clip.w > 0.0 ? std::max(std::fabs(px), std::fabs(py)) : INFINITY;
      if (!(miss <= 0.5 + slack)) {
        ++off;
        worst = std::max(worst, std::isfinite(miss) ? miss : 1e30);
      }
    }
  if (off == 0) return;
  char line[320];
  std::snprintf(
      line, sizeof line,
      "%llu of %llu covered pixels show a point that frame %d's camera puts elsewhere (up to %.3g pixels "
      "away): the frame was not seen from where its camera stands",
      static_cast<unsigned long long>(off), static_cast<unsigned long long>(covered), ctx.options.check_frame,
      worst);
  r.add(
      {Status::failed_check,
       "camera",
       line,
       {{"pixels", double(off)}, {"percent", 100.0 * double(off) / double(covered)}, {"max_pixels", worst}}});
}

}  // namespace omnishadow::bench
