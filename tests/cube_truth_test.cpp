// The cube truth's own rules, without a device: the first surface a back-face-culling rasteriser keeps along
// a ray, and the texel judge's allowance for a fragment whose centre the coverage reached from outside its
// triangle (the attributes extrapolate the triangle's plane to the centre).

#include "bench/truth/cube_truth.h"

#include <gtest/gtest.h>

#include <cmath>

namespace omnishadow::bench {
namespace {

// A square quad across the +X axis at x = `at`, facing -x (towards the origin: kept by a pass culling back
// faces) or +x (culled), as two triangles counter-clockwise from the side they face.
void add_quad(scene::Scene& s, float at, bool faces_origin) {
  const glm::vec3 a(at, -1, -1), b(at, 1, -1), c(at, 1, 1), d(at, -1, 1);
  const glm::vec3 tris[2][3] = {{a, b, c}, {a, c, d}};
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k)
      s.vertices.push_back(
          {faces_origin ? t[2 - k] : t[k], glm::vec3(faces_origin ? -1 : 1, 0, 0), glm::vec3(1)});
}

scene::Scene quads(std::initializer_list<std::pair<float, bool>> list) {
  scene::Scene s;
  s.name = "quads";
  for (const auto& [at, faces_origin] : list) add_quad(s, at, faces_origin);
  scene::Object o;
  o.name = "quads";
  o.vertex_count = uint32_t(s.vertices.size());
  o.cull_back_faces = true;
  s.objects.push_back(o);
  return s;
}

// A culled face a hair before a kept one (a box's silhouette edge, where its culled side and its lit side
// meet at one distance, is the limit): one search among the kept triangles finds the kept face; walking from
// hit to hit (past the culled face by a fixed step) went past it too.
TEST(CubeTruth, TheFirstKeptSurfaceIsFoundJustBehindACulledOne) {
  const scene::Scene s = quads({{5.0f, false}, {5.00005f, true}});
  const reference::RayCaster caster(s);
  const std::vector<uint8_t> culled = culled_triangles(s, CulledFaces::back);
  const glm::vec3 origin(0.0f, 0.25f, -0.5f), unit(1.0f, 0.0f, 0.0f);
  EXPECT_NEAR(first_kept_hit(caster, s, culled, origin, unit, 10.0), 5.00005, 1e-6);
  // Two-sided (nothing culled): the nearer face.
  EXPECT_NEAR(first_kept_hit(caster, s, culled_triangles(s, CulledFaces::none), origin, unit, 10.0), 5.0,
              1e-6);
  // Only the culled face: nothing.
  const scene::Scene back = quads({{5.0f, false}});
  EXPECT_EQ(first_kept_hit(reference::RayCaster(back), back, culled_triangles(back, CulledFaces::back),
                           origin, unit, 10.0),
            -1.0);
}

// plane_at extends the surface a ray meets to another ray of the face: inside the quad it is that ray's own
// distance, and past the quad's edge it is where the quad's plane (x = 5) crosses the ray, 5 / u.x.
TEST(CubeTruth, ASurfacesPlaneIsExtendedToTheCentresRay) {
  const scene::Scene s = quads({{5.0f, true}});
  const reference::RayCaster caster(s);
  const CubeTruth truth = compute_cube_truth(caster, s, glm::vec3(0.0f), 0.1f, 20.0f, 8, false);
  ASSERT_TRUE(truth.plane_at);
  // The quad spans |y|, |z| <= 1 at x = 5: texel rays of +X within about 0.2 of the axis meet it.
  EXPECT_NEAR(truth.plane_at(0, 4.1, 4.2, 3.9, 4.0), truth.cast(0, 3.9, 4.0), 1e-5);
  const std::optional<LayerRay> outside = layout_geometry::cube_point_ray(0, 0.5, 0.5, 8);  // a corner texel
  ASSERT_TRUE(outside.has_value());
  EXPECT_EQ(truth.cast(0, 0.5, 0.5), -1.0);  // beyond the quad
  EXPECT_NEAR(truth.plane_at(0, 4.1, 4.2, 0.5, 0.5), 5.0 / outside->unit.x, 1e-5);
  EXPECT_EQ(truth.plane_at(0, 0.5, 0.5, 4.0, 4.0), -1.0);  // a ray that meets nothing has no plane
}

// The judge: a stored surface at a centre whose ray meets nothing, next to an edge whose far side the corners
// meet, agrees when it is that surface's plane at the centre (interpolation past the edge), and still not
// when it is off the plane by more than the storage's agreement.
TEST(CubeTruth, ACentreJustOutsideItsTriangleMayHoldTheTrianglesPlane) {
  auto agree = [](double got, double want) { return std::fabs(got - want) <= 1e-4 * want; };
  const TexelSample nothing{false, 0.0};
  const std::vector<TexelSample> corners = {
      nothing, {true, 1.76587, 1.76587, 1.76723}, nothing, {true, 1.76600, 1.76600, 1.76723}};
  auto reach = [&] { return corners; };
  EXPECT_EQ(judge_texel({true, 1.76723}, nothing, agree, reach), TexelVerdict::ok);
  EXPECT_EQ(judge_texel({true, 1.80}, nothing, agree, reach), TexelVerdict::spurious);
  const std::vector<TexelSample> no_plane = {nothing, {true, 1.76587}, nothing, {true, 1.76600}};
  EXPECT_EQ(judge_texel({true, 1.76723}, nothing, agree, [&] { return no_plane; }), TexelVerdict::spurious);
}

// A steep triangle whose edge runs between a texel's centre and its left corners, 1/256 texel from the
// centre: the rasteriser may cover the centre from a point between the two, and that point's distance lies
// beyond every corner's (the left corners meet nothing, the right ones nearer parts of the slope). The judge
// bounds it by the triangle's plane over the whole reach square: it accepts the edge's value, on both the
// storages that write a distance and hardware_depth (the axis depth there, scaled by the centre's ray), and
// still rejects the plane one step beyond the square.
TEST(CubeTruth, ASteepEdgeInsideTheReachSquareBoundsByItsPlane) {
  constexpr int kSize = 8, kBits = 8;
  const double step = std::ldexp(1.0, -kBits), edge = 4.5 - step;
  auto on_ray = [](double s, double t, double distance) {
    return glm::vec3(layout_geometry::cube_point_ray(0, s, t, kSize)->unit * distance);
  };
  // The edge at s = `edge` for every t (a constant-s line of +X is a plane through the light), 5 away, the
  // far vertex 2 away: about 0.9 units a texel along s, ten times the 1e-4 of the distance allowed.
  scene::Scene s;
  s.name = "slope";
  for (const glm::vec3& p : {on_ray(edge, 0.0, 5.0), on_ray(edge, 8.0, 5.0), on_ray(8.0, 4.5, 2.0)})
    s.vertices.push_back({p, glm::vec3(-1, 0, 0), glm::vec3(1)});
  scene::Object o;
  o.name = "slope";
  o.vertex_count = 3;
  s.objects.push_back(o);  // two-sided: its winding does not matter
  const reference::RayCaster caster(s);
  const float near_plane = 0.1f, far_plane = 20.0f;
  const CubeTruth truth = compute_cube_truth(caster, s, glm::vec3(0.0f), near_plane, far_plane, kSize, true);
  const double reach = raster_reach_texels(kBits);
  ASSERT_GE(truth.cast(0, 4.5, 4.5), 0.0);
  ASSERT_EQ(truth.cast(0, 4.5 - reach, 4.5 - reach), -1.0);
  double corners_max = -1.0;
  for (double dt : {-reach, reach}) corners_max = std::max(corners_max, truth.cast(0, 4.5 + reach, 4.5 + dt));
  const double at_edge = truth.plane_at(0, 5.0, 4.5, edge + 1e-6, 4.5);
  EXPECT_GT(at_edge, corners_max + 1e-3 * at_edge) << "the corners alone would not bound it";
  auto admissible = [&](Storage storage, double stored) {
    return texel_admissible(truth, storage, DepthFormat::d32f, near_plane, far_plane, kBits, 0, 4, 4, stored);
  };
  const double beyond = truth.plane_at(0, 5.0, 4.5, 4.5 - reach - step, 4.5);
  EXPECT_TRUE(admissible(Storage::linear_depth, at_edge));
  EXPECT_FALSE(admissible(Storage::linear_depth, beyond));
  // hardware_depth reads back the axis depth times the centre's depth-to-distance.
  auto as_read = [&](double distance, double s_at) {
    return distance / layout_geometry::cube_point_ray(0, s_at, 4.5, kSize)->depth_to_distance *
           layout_geometry::cube_point_ray(0, 4.5, 4.5, kSize)->depth_to_distance;
  };
  EXPECT_TRUE(admissible(Storage::hardware_depth, as_read(at_edge, edge)));
  EXPECT_FALSE(admissible(Storage::hardware_depth, as_read(beyond, 4.5 - reach - step)));
}

}  // namespace
}  // namespace omnishadow::bench
