#include "bench/truth/map_truth.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <cmath>
#include <cstdio>

#include "backends/common/map_lights.h"
#include "bench/truth/cube_truth.h"

namespace omnishadow::bench {

MapTruth compute_map_truth(const reference::RayCaster& caster, const scene::Scene& scene, int frame, int map_size,
                           cube::DepthRange range) {
  MapTruth t;
  t.size = map_size;
  t.stride = map_size > kMapTruthGrid ? map_size / kMapTruthGrid : 1;
  const int n = map_size / t.stride;
  const bool zo = range == cube::DepthRange::zero_to_one;
  for (const scene::MapLight& light : scene.map_lights) {
    const glm::mat4 view_proj = gpu::map_view_projection(scene, light, frame, range);
    const glm::mat4 inverse = glm::inverse(view_proj);
    const std::vector<uint8_t> culled =
        culled_triangles(scene, light.cull_front_faces ? CulledFaces::front : CulledFaces::back);
    auto unproject = [&](float x, float y, float z) {
      glm::vec4 p = inverse * glm::vec4(x, y, z, 1.0f);
      return glm::dvec3(p) / double(p.w);
    };
    std::vector<float> out(size_t(n) * size_t(n), 1.0f);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int s = x * t.stride + t.stride / 2, tt = y * t.stride + t.stride / 2;
        const float nx = 2.0f * (float(s) + 0.5f) / float(map_size) - 1.0f;
        const float ny = 2.0f * (float(tt) + 0.5f) / float(map_size) - 1.0f;
        // From the near plane (a hair before it, as the cube's rays) to the far plane through the texel centre.
        const glm::dvec3 near_point = unproject(nx, ny, zo ? 0.0f : -1.0f), far_point = unproject(nx, ny, 1.0f);
        const glm::dvec3 along = far_point - near_point;
        const double length = glm::length(along);
        const glm::dvec3 unit = along / length;
        const glm::dvec3 start = near_point - unit * (1e-5 * length);
        const double hit = first_kept_hit(caster, scene, culled, glm::vec3(start), glm::vec3(unit), length * 1.00002);
        if (hit < 0.0) continue;
        const glm::dvec3 point = start + unit * hit;
        const glm::dvec4 clip = glm::dmat4(view_proj) * glm::dvec4(point, 1.0);
        const double ndc_z = clip.z / clip.w;
        out[size_t(y) * size_t(n) + size_t(x)] = float(zo ? ndc_z : 0.5 * ndc_z + 0.5);
      }
    t.depth.push_back(std::move(out));
  }
  return t;
}

MapTexelReport check_map_texels(const MapTruth& truth, const Images& images, DepthFormat format) {
  MapTexelReport r;
  r.stride = truth.stride;
  const double step = format == DepthFormat::d16 ? 1.0 / 65535.0 : format == DepthFormat::d24 ? 1.0 / 16777215.0 : 0.0;
  const int n = truth.size / truth.stride;
  for (size_t m = 0; m < truth.depth.size() && m < images.map_depth.size(); ++m) {
    uint64_t bad = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const size_t s = size_t(x * truth.stride + truth.stride / 2), t = size_t(y * truth.stride + truth.stride / 2);
        const double stored = images.map_depth[m][t * size_t(truth.size) + s];
        const double exact = truth.depth[m][size_t(y) * size_t(n) + size_t(x)];
        const bool stored_surface = stored < 1.0, exact_surface = exact < 1.0;
        ++r.texels;
        const double bound = 2.0 * (step > 0 ? step : std::ldexp(std::fabs(exact), -23)) + 1e-5;
        if (stored_surface && exact_surface) {
          const double error = std::fabs(stored - exact);
          r.max_error = std::max(r.max_error, error);
          if (error > bound) ++r.wrong, ++bad;
        } else if (stored_surface != exact_surface && std::fabs(stored - exact) > bound) {
          // A surface at the far plane itself stores ~1: only a real difference counts.
          ++(stored_surface ? r.spurious : r.missing), ++bad;
        }
      }
    r.bad_per_map.push_back(bad);
  }
  return r;
}

std::string describe(const MapTexelReport& r) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "map_texels: %.3g%% of %llu texels wrong (", r.bad_percent(),
                static_cast<unsigned long long>(r.texels));
  std::string out = buf;
  const uint64_t per_map = r.bad_per_map.empty() ? 0 : r.texels / r.bad_per_map.size();
  for (size_t m = 0; m < r.bad_per_map.size(); ++m) {
    std::snprintf(buf, sizeof buf, "%smap %zu %.3g%%", m ? ", " : "", m,
                  per_map ? 100.0 * double(r.bad_per_map[m]) / double(per_map) : 0.0);
    out += buf;
  }
  std::snprintf(buf, sizeof buf, "), max depth error %.3g", r.max_error);
  return out + buf;
}

}  // namespace omnishadow::bench
