// The checks of what each frame needs with many lights: culling to the view (every covered pixel's taps read
// faces the frame drew) and clustered light lists (every light that reaches a covered pixel is in its
// cluster's list). Both replay the frame from the read-back world positions, independently of the code that
// decided what to draw and list, over every light of the case.

#include <algorithm>
#include <array>
#include <cmath>

#include "backends/common/cube_faces.h"
#include "backends/common/light_clusters.h"
#include "bench/truth/case_checks.h"
#include "bench/truth/lookup_check.h"

namespace omnishadow::bench {

namespace {

// The world offsets a filter's taps add to the lookup vector (shaders/shadow_filters.glsl, its disk table
// read from the shader source by the lookup replay), for a point `view_distance` from the camera. PCSS's
// penumbra has no bound (its light keeps every face): only its centre tap.
std::vector<glm::vec3> tap_offsets(const CaseConfig& c, float view_distance, float range) {
  const float scale = c.pcf_scale;
  std::vector<glm::vec3> taps;
  if (c.filter == Filter::pcf_grid64) {
    const float grid = 0.1f * scale, step = grid / 2.0f;
    for (int x = 0; x < 4; ++x)
      for (int y = 0; y < 4; ++y)
        for (int z = 0; z < 4; ++z) taps.push_back(glm::vec3(-grid) + step * glm::vec3(x, y, z));
  } else if (c.filter == Filter::pcf_disk20) {
    const float radius = (1.0f + view_distance / range) / 25.0f * scale;
    for (const glm::dvec3& d : disk_directions()) taps.push_back(glm::vec3(d) * radius);
  } else {
    taps.push_back(glm::vec3(0.0f));
  }
  return taps;
}

}  // namespace

// View culling's own check, over every light (not only the checked ones), independent of the culling's
// geometry: every tap of every covered pixel within a light's range (the filter's kernel replayed from the
// pixel's world position) reads faces the frame drew. It skips the normal offset's shift (the normal is not
// read back); the comparison with six_pass unculled (reference_config) still holds the lit frame to the
// unculled one.
void check_view_culling(CaseFindings& r, const Images& images, const std::vector<PlannedLight>& lights,
                        const glm::vec3& camera) {
  if (!r.config.optimizations.view_culling) return;
  const std::vector<float>& p = images.world_position;
  uint64_t total = 0;
  std::string where;
  for (const PlannedLight& light : lights) {
    std::array<uint64_t, 6> missing{};
    for (size_t i = 0; i + 3 < p.size(); i += 4) {
      if (p[i + 3] != 1.0f) continue;  // nothing drawn here
      const glm::vec3 point(p[i], p[i + 1], p[i + 2]);
      const glm::vec3 d = point - light.position;
      if (glm::length(d) >= light.range) continue;  // beyond the range: the light adds nothing
      uint8_t read = 0;
      for (const glm::vec3& tap : tap_offsets(r.config, glm::length(camera - point), light.range))
        read |= cube::faces_within(d + tap, 0.5f, light.face_size);        // a LINEAR tap's half texel
      if (light.faces == 0) read = 1u << cube::direction_to_face(d).face;  // a light out of view: any pixel
      for (int f = 0; f < 6; ++f) missing[size_t(f)] += (read & ~light.faces) >> f & 1u;
    }
    for (int f = 0; f < 6; ++f) {
      if (!missing[size_t(f)]) continue;
      total += missing[size_t(f)];
      where += std::string(where.empty() ? "" : ", ") + "light " + std::to_string(light.index) + " " +
               cube::kFaceNames[size_t(f)] + ": " + std::to_string(missing[size_t(f)]);
    }
  }
  if (total == 0) return;
  r.add({Status::failed_check,
         "view_culling",
         std::to_string(total) +
             " covered pixels within a light's range read it through faces view culling "
             "left out (" +
             where + ")",
         {{"pixels", double(total)}}});
}

// The clustered lists the backend built for the check frame, rebuilt here from the same lights, against every
// light's distance to every covered pixel: a light within range of a pixel and missing from the pixel's
// cluster fails the case. Also the lists' figures: the lights a covered pixel's cluster lists and the lights
// that actually reach it, on average.
void check_light_clusters(CaseFindings& r, const Images& images, const std::vector<PlannedLight>& lights,
                          const scene::Camera& camera) {
  if (!r.config.optimizations.light_clusters || images.width < 1) return;
  LightClusterReport& report = r.light_clusters.emplace();
  const gpu::ClusterGrid grid = gpu::cluster_grid(camera, images.width, images.height);
  std::vector<gpu::ClusterLight> listed;
  for (const PlannedLight& l : lights) listed.push_back({l.position, l.range});
  const std::vector<uint32_t> words = gpu::build_light_clusters(grid, listed);
  report.clusters = grid.clusters();
  const std::vector<float>& p = images.world_position;
  uint64_t missing = 0, pixels = 0, listed_sum = 0, reaching_sum = 0;
  for (size_t i = 0; i + 3 < p.size(); i += 4) {
    if (p[i + 3] != 1.0f) continue;  // nothing drawn here
    const size_t pixel = i / 4;
    const glm::vec3 point(p[i], p[i + 1], p[i + 2]);
    const int c =
        gpu::cluster_of(grid, int(pixel % size_t(images.width)), int(pixel / size_t(images.width)), point);
    const uint32_t first = words[gpu::kClusterHeaderWords + 2 * size_t(c)];
    const uint32_t count = words[gpu::kClusterHeaderWords + 2 * size_t(c) + 1];
    const auto begin = words.begin() + first, end = begin + count;
    ++pixels;
    listed_sum += count;
    report.max_listed = std::max(report.max_listed, int(count));
    for (const PlannedLight& l : lights) {
      if (glm::length(point - l.position) >= l.range) continue;
      ++reaching_sum;
      missing += !std::binary_search(begin, end, uint32_t(l.index));
    }
  }
  if (pixels) {
    report.mean_listed = double(listed_sum) / double(pixels);
    report.mean_reaching = double(reaching_sum) / double(pixels);
  }
  if (missing == 0) return;
  r.add({Status::failed_check,
         "light_clusters",
         std::to_string(missing) + " (pixel, light) pairs where the light reaches the covered pixel and its "
                                   "cluster does not list it",
         {{"missing", double(missing)}}});
}

}  // namespace omnishadow::bench
