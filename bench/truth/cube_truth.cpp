#include "bench/truth/cube_truth.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <future>
#include <memory>

#include "backends/common/cube_faces.h"
#include "backends/common/paraboloid.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/tetrahedron.h"

namespace omnishadow::bench {

std::vector<uint8_t> culled_triangles(const scene::Scene& scene, CulledFaces closed_objects) {
  std::vector<uint8_t> culled(scene.vertices.size() / 3, uint8_t(CulledFaces::none));
  for (const scene::Object& o : scene.objects)
    if (o.cull_back_faces)
      for (uint32_t v = o.first_vertex; v < o.first_vertex + o.vertex_count; v += 3)
        culled[v / 3] = uint8_t(closed_objects);
  return culled;
}

reference::Hit first_kept(const reference::RayCaster& caster, const scene::Scene& scene,
                          const std::vector<uint8_t>& culled, const glm::vec3& origin, const glm::vec3& unit,
                          double length) {
  // One search among the kept triangles: stepping past a culled hit would skip a kept face at the same
  // distance (a box's silhouette edge, where its culled side meets its lit side: a lamp's ray along a
  // pillar's corner read "nothing" where the rasteriser drew the pillar).
  return caster.closest_kept(origin, unit, length, [&](uint32_t tri) {
    if (culled[tri] == uint8_t(CulledFaces::none)) return true;
    const glm::vec3 a = scene.vertices[3 * size_t(tri)].position,
                    b = scene.vertices[3 * size_t(tri) + 1].position,
                    c = scene.vertices[3 * size_t(tri) + 2].position;
    const bool front = glm::dot(glm::cross(b - a, c - a), unit) < 0.0f;  // counter-clockwise towards the ray
    return front != (culled[tri] == uint8_t(CulledFaces::front));
  });
}

double first_kept_hit(const reference::RayCaster& caster, const scene::Scene& scene,
                      const std::vector<uint8_t>& culled, glm::vec3 origin, const glm::vec3& unit,
                      double length) {
  const reference::Hit hit = first_kept(caster, scene, culled, origin, unit, length);
  return hit.hit ? hit.distance : -1.0;
}

CubeTruth compute_cube_truth(const reference::RayCaster& caster, const scene::Scene& scene,
                             const glm::vec3& light, float near_plane, float far_plane, int cube_size,
                             bool two_sided, const TexelGeometry& geometry) {
  auto culled = std::make_shared<const std::vector<uint8_t>>(
      culled_triangles(scene, two_sided ? CulledFaces::none : CulledFaces::back));
  CubeTruth t;
  t.geometry = &geometry;
  t.size = cube_size;
  t.stride = cube_sample_stride(cube_size);
  t.far_plane = far_plane;
  // The first kept surface along layer `face`'s ray through (s, t), and where the ray starts.
  auto layer_hit = [caster = &caster, scene = &scene, culled, light, near_plane, far_plane, cube_size,
                    ray_at = geometry.point_ray](int face, double s, double tt) {
    const std::optional<LayerRay> ray = ray_at(face, s, tt, cube_size);
    if (!ray) return std::pair{-1.0, reference::Hit{}};
    // The layer clips at near and far (axis distances for a perspective face, radial for a paraboloid). A
    // surface lying exactly on the near plane is kept by the rasteriser (the room's cube face at x = -1 with
    // the light at the origin and near 1), so the ray starts a hair before it.
    const glm::vec3 unit(ray->unit);
    const double start = double(near_plane) * ray->depth_to_distance * (1.0 - 1e-5),
                 end = double(far_plane) * ray->depth_to_distance;
    return std::pair{start,
                     first_kept(*caster, *scene, *culled, light + unit * float(start), unit, end - start)};
  };
  t.cast = [layer_hit](int face, double s, double tt) {
    const auto [start, hit] = layer_hit(face, s, tt);
    return hit.hit ? start + hit.distance : -1.0;
  };
  // The plane of the triangle a hit lies on; none off a perspective projection (see plane_at).
  auto hit_plane = [scene = &scene, light, planar = geometry.map != TexelMap::paraboloid](
                       const reference::Hit& hit) -> std::optional<SurfacePlane> {
    if (!planar || !hit.hit) return std::nullopt;
    const glm::dvec3 a(scene->vertices[3 * size_t(hit.triangle)].position),
        b(scene->vertices[3 * size_t(hit.triangle) + 1].position),
        c(scene->vertices[3 * size_t(hit.triangle) + 2].position);
    const glm::dvec3 normal = glm::cross(b - a, c - a);
    return SurfacePlane{normal, glm::dot(a - glm::dvec3(light), normal)};
  };
  t.cast_with_plane = [layer_hit, hit_plane](int face, double s, double tt) {
    const auto [start, hit] = layer_hit(face, s, tt);
    return std::pair{hit.hit ? start + hit.distance : -1.0, hit_plane(hit)};
  };
  if (geometry.map != TexelMap::paraboloid) {
    t.plane_along = [cube_size, ray_at = geometry.point_ray](const SurfacePlane& plane, int face, double cs,
                                                             double ct) {
      const std::optional<LayerRay> ray = ray_at(face, cs, ct, cube_size);
      if (!ray) return -1.0;
      const double towards = glm::dot(ray->unit, plane.normal);
      if (std::fabs(towards) <= 1e-9 * glm::length(plane.normal)) return -1.0;  // the ray runs along it
      const double d = plane.offset / towards;
      return d > 0.0 ? d : -1.0;
    };
    t.plane_at = [layer_hit, hit_plane, along = t.plane_along](int face, double s, double tt, double cs,
                                                               double ct) {
      const std::optional<SurfacePlane> plane = hit_plane(layer_hit(face, s, tt).second);
      return plane ? along(*plane, face, cs, ct) : -1.0;
    };
  }
  const int n = cube_size / t.stride;
  auto face_truth = [&](int face) {
    std::vector<float> out(size_t(n) * size_t(n), -1.0f);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int s = x * t.stride + t.stride / 2, tt = y * t.stride + t.stride / 2;
        out[size_t(y) * size_t(n) + size_t(x)] = float(t.cast(face, s + 0.5, tt + 0.5));
      }
    return out;
  };
  std::array<std::future<std::vector<float>>, 6> faces;
  for (int f = 0; f < geometry.layers; ++f) faces[size_t(f)] = std::async(std::launch::async, face_truth, f);
  for (int f = 0; f < geometry.layers; ++f) t.distance[size_t(f)] = faces[size_t(f)].get();
  return t;
}

namespace {

double storage_step(Storage storage, DepthFormat format, double distance, double axis, double near_plane,
                    double far_plane) {
  const double q = format == DepthFormat::d16   ? 1.0 / 65535.0
                   : format == DepthFormat::d24 ? 1.0 / 16777215.0
                                                : std::ldexp(1.0, -23);
  switch (traits(storage).checked) {
    case DistanceEncoding::linear_depth:
      return far_plane * q;
    case DistanceEncoding::colour_distance:
      return distance * std::ldexp(1.0, -23);
    case DistanceEncoding::projective_depth:
      // d(axis)/d(window depth) = axis^2 (f - n) / (n f), along the texel's direction; GL's [-1, 1] range
      // doubles the window-depth step.
      return 2.0 * axis * axis * (far_plane - near_plane) / (near_plane * far_plane) * q * (distance / axis);
  }
  return 0.0;
}

}  // namespace

// Whether a read-back distance is a surface rather than "nothing here", the clear value. linear_depth clamps
// at far (a surface beyond it reads as the clear); r32f's clear is FLT_MAX and hardware_depth's reads back as
// far exactly, while a surface they hold may lie beyond far along a texel ray that leaves the face's axis (a
// cube's corners reach sqrt 3 far): the hall's lamps, whose range is shorter than the room, show it.
static bool stored_surface(Storage storage, double got, double far_plane) {
  switch (traits(storage).checked) {
    case DistanceEncoding::linear_depth:
      return got < far_plane * (1.0 - 1e-6);
    case DistanceEncoding::colour_distance:
      return got != double(FLT_MAX);
    case DistanceEncoding::projective_depth:
      break;
  }
  return got != far_plane;
}

// What the storage reports for a point (cs, ct) of the square of half-side `reach` around the centre (s, t):
// its distance for the storages that compute one per fragment; hardware_depth stores the point's axis depth
// and the read-back scales it by the centre's direction (cube::projective_depth_to_distance), so the same
// scaling (`scale(x, y)`: the centre's depth-to-distance over the point's) applies here. Also the range the
// point's surface spans over the whole square (its plane at the four corners and along the centre's own ray,
// scaled alike): a fragment of that triangle may cover the centre from any point of the square, its edge
// included, and where the edge crosses the square the triangle's extreme lies there, between the corners.
template <typename Scale>
static TexelSample reach_sample(const CubeTruth& truth, Storage storage, double far_plane, int f, double cs,
                                double ct, double s, double t, double reach, Scale scale) {
  const bool clamps_at_far = traits(storage).checked == DistanceEncoding::linear_depth;
  const bool scaled = traits(storage).checked == DistanceEncoding::projective_depth;
  // One ray for both: the point's distance and its surface's plane.
  auto [d, plane] = truth.cast_with_plane ? truth.cast_with_plane(f, cs, ct)
                                          : std::pair{truth.cast(f, cs, ct), std::optional<SurfacePlane>{}};
  if (clamps_at_far && d >= far_plane) d = -1.0;
  if (d >= 0.0 && scaled) d *= scale(cs, ct);
  TexelSample out{d >= 0.0, d};
  if (d < 0.0 || !plane || !truth.plane_along) return out;
  const double square[5][2] = {
      {s, t}, {s - reach, t - reach}, {s + reach, t - reach}, {s - reach, t + reach}, {s + reach, t + reach}};
  for (const auto& [x, y] : square) {
    double v = truth.plane_along(*plane, f, x, y);
    if (v < 0.0) continue;  // the plane turns edge-on within the square: its other points still bound it
    if (scaled) v *= scale(x, y);
    if (clamps_at_far) v = std::min(v, far_plane);  // beyond far the fragment stores the clear
    out.plane_lo = out.plane_lo < 0.0 ? v : std::min(out.plane_lo, v);
    out.plane_hi = std::max(out.plane_hi, v);
  }
  return out;
}

namespace {

// What one texel's judgement needs besides the texel: the truth, the storage and the rasteriser's reach.
struct TexelRule {
  const CubeTruth& truth;
  Storage storage;
  DepthFormat format;
  float near_plane;
  double far_plane;
  double reach_texels;
};

// One texel's judgement: `got` (read back) at texel (s, t) of layer f against `want` (the exact distance at
// its centre, -1 for nothing). `want` comes back as judged (-1 where a clamping storage reads a surface
// beyond far as nothing), and `got_surface` says whether `got` is a surface.
TexelVerdict judge_cube_texel(const TexelRule& rule, int f, int s, int t, double got, double& want,
                              bool& got_surface) {
  const CubeTruth& truth = rule.truth;
  const Storage storage = rule.storage;
  const double far_plane = rule.far_plane;
  // Depth storages hold min(distance / far, 1): a surface farther than the light's far (along a texel ray
  // whose axis distance is within it: a cube's corners reach sqrt 3 far) is the clear value, as it is to
  // every lookup. A light whose range is shorter than its room (the hall's lamps) has many such texels.
  const bool clamps_at_far = traits(storage).checked == DistanceEncoding::linear_depth;
  // Distance over the stored depth's measure at a point of layer f: axis distance for a perspective face, 1
  // where the depth is radial (the paraboloid's).
  auto depth_to_distance = [&](double cs, double ct) {
    const std::optional<LayerRay> ray = truth.geometry->point_ray(f, cs, ct, truth.size);
    return ray ? ray->depth_to_distance : 1.0;
  };
  got_surface = stored_surface(storage, got, far_plane);
  const double len = depth_to_distance(s + 0.5, t + 0.5);
  auto agree = [&](double stored_distance, double exact_distance) {
    return std::fabs(stored_distance - exact_distance) <=
           2.0 * storage_step(storage, rule.format, exact_distance, exact_distance / len, rule.near_plane,
                              far_plane) +
               1e-4 * exact_distance;
  };
  if (clamps_at_far && want >= 0.0) {
    // Within the storage's agreement of far either answer is right; beyond it only "nothing".
    if (!got_surface && agree(far_plane, std::min(want, far_plane))) return TexelVerdict::ok;
    if (want >= far_plane && !(got_surface && agree(got, want))) want = -1.0;
  }
  auto scale = [&](double cs, double ct) { return len / depth_to_distance(cs, ct); };
  auto cast = [&](double cs, double ct) {
    return reach_sample(truth, storage, far_plane, f, cs, ct, s + 0.5, t + 0.5, rule.reach_texels, scale);
  };
  return judge_texel({got_surface, got}, {want >= 0.0, want}, agree, [&] {
    // The centre's own surface spans its plane's range over the square too.
    std::vector<TexelSample> reach = reach_corners(s + 0.5, t + 0.5, rule.reach_texels, cast);
    reach.push_back(cast(s + 0.5, t + 0.5));
    return reach;
  });
}

}  // namespace

bool texel_admissible(const CubeTruth& truth, Storage storage, DepthFormat format, float near_plane,
                      float far_plane, int subpixel_bits, int layer, int s, int t, double stored) {
  const TexelRule rule{truth, storage, format, near_plane, far_plane, raster_reach_texels(subpixel_bits)};
  double want = double(float(truth.cast(layer, s + 0.5, t + 0.5)));  // as compute_cube_truth's grid holds it
  bool got_surface = false;
  return judge_cube_texel(rule, layer, s, t, stored, want, got_surface) == TexelVerdict::ok;
}

CubeTexelReport check_cube_texels(const CubeTruth& truth, const Images& images, Storage storage,
                                  DepthFormat format, float near_plane, int subpixel_bits) {
  CubeTexelReport r;
  const TexelGeometry& geometry = *truth.geometry;
  r.geometry = truth.geometry;
  r.stride = truth.stride;
  r.reach_texels = raster_reach_texels(subpixel_bits);
  WorstTexels worst;
  const int n = truth.size / truth.stride;
  if (images.cube_size != truth.size) return r;
  if (!images.has_full_cube() &&
      (images.cube_sample_stride != truth.stride || images.cube_sample[0].size() != size_t(n * n)))
    return r;
  const TexelRule rule{truth, storage, format, near_plane, images.light_far, r.reach_texels};
  for (int f = 0; f < geometry.layers; ++f) {
    if (!images.face_drawn(f)) continue;  // view culling left it out: no visible pixel reads it
    // The check grid is the truth's grid: read from the device's sample, or from the full cube where it came
    // back.
    const bool full = images.has_full_cube();
    const auto& stored = full ? images.cube_distance[size_t(f)] : images.cube_sample[size_t(f)];
    const auto& exact = truth.distance[size_t(f)];
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int s = x * truth.stride + truth.stride / 2, t = y * truth.stride + truth.stride / 2;
        if (!geometry.texel_read(s, t, truth.size)) continue;
        const double got =
            full ? stored[size_t(t) * size_t(truth.size) + size_t(s)] : stored[size_t(y * n + x)];
        double want = exact[size_t(y) * size_t(n) + size_t(x)];
        ++r.texels;
        bool got_surface = false;
        const TexelVerdict v = judge_cube_texel(rule, f, s, t, got, want, got_surface);
        if (got_surface && want >= 0.0) r.max_error = std::max(r.max_error, std::fabs(got - want));
        if (v == TexelVerdict::ok) continue;
        ++(v == TexelVerdict::wrong ? r.wrong : v == TexelVerdict::spurious ? r.spurious : r.missing);
        ++r.bad_per_face[size_t(f)];
        worst.add({f, s, t, got_surface ? got : -1.0, want});
      }
  }
  for (TexelFinding& w : worst.list())
    w.edge_texels = edge_distance_texels(w.s + 0.5, w.t + 0.5, [&](double cs, double ct) {
      const double d = truth.cast(w.layer, cs, ct);
      return TexelSample{d >= 0.0, d};
    });
  r.worst = std::move(worst.list());
  return r;
}

std::string describe(const CubeTexelReport& r) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "cube_texels: %.3g%% of %llu texels (every %d%s) wrong", r.bad_percent(),
                static_cast<unsigned long long>(r.texels), r.stride, r.stride == 1 ? "" : "th in s and t");
  std::string out = buf;
  std::string faces;
  const TexelGeometry& geometry = *r.geometry;
  const char* const* names = geometry.layer_names.data();
  const uint64_t per_face = r.texels / uint64_t(geometry.layers);  // a paraboloid's: texels of the disk
  for (int f = 0; f < geometry.layers; ++f)
    if (r.bad_per_face[size_t(f)] && per_face) {
      std::snprintf(buf, sizeof buf, "%s %.3g%%", names[f],
                    100.0 * double(r.bad_per_face[size_t(f)]) / double(per_face));
      faces += (faces.empty() ? "" : ", ") + std::string(buf);
    }
  if (!faces.empty()) out += " (" + faces + ")";
  std::snprintf(buf, sizeof buf,
                ": %llu beyond the depth step, %llu spurious, %llu missing, max error %.4g units",
                static_cast<unsigned long long>(r.wrong), static_cast<unsigned long long>(r.spurious),
                static_cast<unsigned long long>(r.missing), r.max_error);
  return out + buf + describe_worst(r.worst, "", names);
}

}  // namespace omnishadow::bench
