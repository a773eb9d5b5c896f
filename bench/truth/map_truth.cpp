#include "bench/truth/map_truth.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_inverse.hpp>
#include <memory>
#include <utility>
#include <vector>

#include "backends/common/map_lights.h"
#include "bench/truth/cube_truth.h"

namespace omnishadow::bench {

namespace {

// Every map light's rays, casts and planes: what MapTruth's functions hold (by pointer to the caster and the
// scene, which the harness's caches outlive the truth with).
class MapRays {
 public:
  MapRays(const reference::RayCaster& caster, const scene::Scene& scene, int frame, int map_size,
          cube::DepthRange range)
      : caster_(&caster), scene_(&scene), map_size_(map_size), zo_(range == cube::DepthRange::zero_to_one) {
    for (const scene::MapLight& light : scene.map_lights) {
      const glm::mat4 view_proj = gpu::map_view_projection(scene, light, frame, range);
      lights_.push_back(
          {glm::dmat4(view_proj), glm::dmat4(glm::inverse(view_proj)),
           culled_triangles(scene, light.cull_front_faces ? CulledFaces::front : CulledFaces::back)});
    }
  }
  size_t lights() const { return lights_.size(); }

  // The window depth of the first kept surface through texel point (x, y) of map m; 1 where none.
  double cast(size_t m, double x, double y) const {
    const auto [hit, point] = first_hit(m, x, y);
    return hit.hit ? window_depth(m, point) : 1.0;
  }

  // cast(m, x, y) with the range its triangle's plane spans over the square of half-side `reach` around (cx,
  // cy): the plane met by each corner's ray (window depth is affine in window coordinates on a plane, so the
  // corners hold its extremes), clamped to the depth range a fragment can store.
  TexelSample sample(size_t m, double x, double y, double cx, double cy, double reach) const {
    const auto [hit, point] = first_hit(m, x, y);
    if (!hit.hit) return TexelSample{false, 1.0};
    TexelSample out{true, window_depth(m, point)};
    const glm::dvec3 a(scene_->vertices[3 * size_t(hit.triangle)].position),
        b(scene_->vertices[3 * size_t(hit.triangle) + 1].position),
        c(scene_->vertices[3 * size_t(hit.triangle) + 2].position);
    const glm::dvec3 normal = glm::cross(b - a, c - a);
    for (const auto& [px, py] : {std::pair{cx - reach, cy - reach}, std::pair{cx + reach, cy - reach},
                                 std::pair{cx - reach, cy + reach}, std::pair{cx + reach, cy + reach}}) {
      const Ray ray = ray_through(m, px, py);
      const glm::dvec3 along = ray.far_point - ray.near_point;
      const double towards = glm::dot(along, normal);
      if (std::fabs(towards) <= 1e-12 * glm::length(along) * glm::length(normal)) continue;  // edge-on
      const glm::dvec3 on_plane = ray.near_point + along * (glm::dot(a - ray.near_point, normal) / towards);
      const double z = std::clamp(window_depth(m, on_plane), 0.0, 1.0);
      out.plane_lo = out.plane_lo < 0.0 ? z : std::min(out.plane_lo, z);
      out.plane_hi = std::max(out.plane_hi, z);
    }
    return out;
  }

 private:
  struct Light {
    glm::dmat4 view_proj, inverse;
    std::vector<uint8_t> culled;
  };
  // A texel point's ray from its near to its far plane, in world space.
  struct Ray {
    glm::dvec3 near_point, far_point;
  };

  Ray ray_through(size_t m, double x, double y) const {
    const Light& l = lights_[m];
    auto unproject = [&](double nx, double ny, double z) {
      const glm::dvec4 p = l.inverse * glm::dvec4(nx, ny, z, 1.0);
      return glm::dvec3(p) / p.w;
    };
    const double nx = 2.0 * x / double(map_size_) - 1.0, ny = 2.0 * y / double(map_size_) - 1.0;
    return Ray{unproject(nx, ny, zo_ ? 0.0 : -1.0), unproject(nx, ny, 1.0)};
  }
  double window_depth(size_t m, const glm::dvec3& world) const {
    const glm::dvec4 clip = lights_[m].view_proj * glm::dvec4(world, 1.0);
    const double ndc_z = clip.z / clip.w;
    return zo_ ? ndc_z : 0.5 * ndc_z + 0.5;
  }
  // The first kept triangle along the ray through (x, y), and the point it is met at.
  std::pair<reference::Hit, glm::dvec3> first_hit(size_t m, double x, double y) const {
    const Ray ray = ray_through(m, x, y);
    const glm::dvec3 along = ray.far_point - ray.near_point;
    const double length = glm::length(along);
    const glm::dvec3 unit = along / length;
    // From the near plane (a hair before it, as the cube's rays) to the far plane through the point.
    const glm::dvec3 start = ray.near_point - unit * (1e-5 * length);
    const reference::Hit hit =
        first_kept(*caster_, *scene_, lights_[m].culled, glm::vec3(start), glm::vec3(unit), length * 1.00002);
    return {hit, start + unit * hit.distance};
  }

  const reference::RayCaster* caster_;
  const scene::Scene* scene_;
  int map_size_;
  bool zo_;
  std::vector<Light> lights_;
};

}  // namespace

MapTruth compute_map_truth(const reference::RayCaster& caster, const scene::Scene& scene, int frame,
                           int map_size, cube::DepthRange range) {
  MapTruth t;
  t.size = map_size;
  t.stride = map_size > kMapTruthGrid ? map_size / kMapTruthGrid : 1;
  auto rays = std::make_shared<const MapRays>(caster, scene, frame, map_size, range);
  t.cast = [rays](size_t m, double x, double y) { return rays->cast(m, x, y); };
  t.sample = [rays](size_t m, double x, double y, double cx, double cy, double reach) {
    return rays->sample(m, x, y, cx, cy, reach);
  };
  const int n = map_size / t.stride;
  for (size_t m = 0; m < rays->lights(); ++m) {
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
          // Each surface met in the square counts with its plane's range over it (texel_bounds.h), the
          // centre's own included.
          auto cast = [&](double x, double y) {
            return truth.sample(m, x, y, s + 0.5, t + 0.5, r.reach_texels);
          };
          std::vector<TexelSample> reach = reach_corners(s + 0.5, t + 0.5, r.reach_texels, cast);
          reach.push_back(cast(s + 0.5, t + 0.5));
          return reach;
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
