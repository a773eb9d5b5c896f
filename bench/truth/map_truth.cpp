#include "bench/truth/map_truth.h"

#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_inverse.hpp>
#include <memory>

#include "backends/common/map_lights.h"
#include "bench/truth/cube_truth.h"

namespace omnishadow::bench {

MapTruth compute_map_truth(const reference::RayCaster& caster, const scene::Scene& scene, int frame,
                           int map_size, cube::DepthRange range) {
  MapTruth t;
  t.size = map_size;
  t.stride = map_size > kMapTruthGrid ? map_size / kMapTruthGrid : 1;
  const bool zo = range == cube::DepthRange::zero_to_one;
  struct Light {
    glm::dmat4 view_proj, inverse;
    std::vector<uint8_t> culled;
  };
  auto lights = std::make_shared<std::vector<Light>>();
  for (const scene::MapLight& light : scene.map_lights) {
    const glm::mat4 view_proj = gpu::map_view_projection(scene, light, frame, range);
    lights->push_back(
        {glm::dmat4(view_proj), glm::dmat4(glm::inverse(view_proj)),
         culled_triangles(scene, light.cull_front_faces ? CulledFaces::front : CulledFaces::back)});
  }
  t.cast = [caster = &caster, scene = &scene, lights, map_size, zo](size_t m, double x, double y) {
    const Light& l = (*lights)[m];
    auto unproject = [&](double nx, double ny, double z) {
      const glm::dvec4 p = l.inverse * glm::dvec4(nx, ny, z, 1.0);
      return glm::dvec3(p) / p.w;
    };
    const double nx = 2.0 * x / double(map_size) - 1.0, ny = 2.0 * y / double(map_size) - 1.0;
    // From the near plane (a hair before it, as the cube's rays) to the far plane through the point.
    const glm::dvec3 near_point = unproject(nx, ny, zo ? 0.0 : -1.0), far_point = unproject(nx, ny, 1.0);
    const glm::dvec3 along = far_point - near_point;
    const double length = glm::length(along);
    const glm::dvec3 unit = along / length;
    const glm::dvec3 start = near_point - unit * (1e-5 * length);
    const double hit =
        first_kept_hit(*caster, *scene, l.culled, glm::vec3(start), glm::vec3(unit), length * 1.00002);
    if (hit < 0.0) return 1.0;
    const glm::dvec4 clip = l.view_proj * glm::dvec4(start + unit * hit, 1.0);
    const double ndc_z = clip.z / clip.w;
    return zo ? ndc_z : 0.5 * ndc_z + 0.5;
  };
  const int n = map_size / t.stride;
  for (size_t m = 0; m < lights->size(); ++m) {
    std::vector<float> out(size_t(n) * size_t(n), 1.0f);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int s = x * t.stride + t.stride / 2, tt = y * t.stride + t.stride / 2;
        out[size_t(y) * size_t(n) + size_t(x)] = float(t.cast(m, s + 0.5, tt + 0.5));
      }
    t.depth.push_back(std::move(out));
  }
  return t;
}

MapTexelReport check_map_texels(const MapTruth& truth, const Images& images, DepthFormat format,
                                int subpixel_bits) {
  MapTexelReport r;
  r.stride = truth.stride;
  r.reach_texels = raster_reach_texels(subpixel_bits);
  WorstTexels worst;
  const double step = format == DepthFormat::d16   ? 1.0 / 65535.0
                      : format == DepthFormat::d24 ? 1.0 / 16777215.0
                                                   : 0.0;
  auto agree = [&](double stored, double exact) {
    return std::fabs(stored - exact) <= 2.0 * (step > 0 ? step : std::ldexp(std::fabs(exact), -23)) + 1e-5;
  };
  const int n = truth.size / truth.stride;
  for (size_t m = 0; m < truth.depth.size() && m < images.map_depth.size(); ++m) {
    uint64_t bad = 0;
    auto cast = [&](double x, double y) {
      const double d = truth.cast(m, x, y);
      return TexelSample{d < 1.0, d};
    };
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int s = x * truth.stride + truth.stride / 2, t = y * truth.stride + truth.stride / 2;
        const double stored = images.map_depth[m][size_t(t) * size_t(truth.size) + size_t(s)];
        const double exact = truth.depth[m][size_t(y) * size_t(n) + size_t(x)];
        ++r.texels;
        if (stored < 1.0 && exact < 1.0) r.max_error = std::max(r.max_error, std::fabs(stored - exact));
        // A surface at the far plane itself stores ~1, as the clear does: equal depths agree whatever they
        // mean.
        if (agree(stored, exact)) continue;
        const TexelVerdict v = judge_texel({stored < 1.0, stored}, {exact < 1.0, exact}, agree, [&] {
          return reach_corners(s + 0.5, t + 0.5, r.reach_texels, cast);
        });
        if (v == TexelVerdict::ok) continue;
        ++(v == TexelVerdict::wrong ? r.wrong : v == TexelVerdict::spurious ? r.spurious : r.missing);
        ++bad;
        worst.add({int(m), s, t, stored < 1.0 ? stored : -1.0, exact < 1.0 ? exact : -1.0});
      }
    r.bad_per_map.push_back(bad);
  }
  for (TexelFinding& w : worst.list())
    w.edge_texels = edge_distance_texels(w.s + 0.5, w.t + 0.5, [&](double x, double y) {
      const double d = truth.cast(size_t(w.layer), x, y);
      return TexelSample{d < 1.0, d};
    });
  r.worst = std::move(worst.list());
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
  return out + buf + describe_worst(r.worst, "map ", nullptr);
}

}  // namespace omnishadow::bench
