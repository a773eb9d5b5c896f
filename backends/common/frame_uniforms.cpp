#include "backends/common/frame_uniforms.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "backends/common/layouts.h"
#include "backends/common/map_lights.h"
#include "backends/common/shadow_plan.h"
#include "backends/common/storage_filter_tables.h"

namespace omnishadow::gpu {

FrameUniforms make_frame_uniforms(const scene::Scene& scene, int frame, const CaseConfig& config,
                                  cube::DepthRange range) {
  const int width = config.width, height = config.height, injected_work = config.injected_work;
  const scene::Camera cam = scene.camera.at(frame);
  const scene::PointLight& light = scene.light();
  const glm::vec3 light_position = light.path.at(frame);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  const float fov = glm::radians(cam.fov_y_degrees);
  // No y flip in either API: both put clip y = -1 on the first row in memory (see cube_faces.h).
  glm::mat4 projection = range == cube::DepthRange::zero_to_one
                             ? glm::perspectiveRH_ZO(fov, aspect, cam.near_plane, cam.far_plane)
                             : glm::perspectiveRH_NO(fov, aspect, cam.near_plane, cam.far_plane);
  FrameUniforms u;
  u.camera_view_proj = projection * glm::lookAtRH(cam.position, cam.target, cam.up);
  const float far_plane = config.optimizations.fit_range
                              ? cube::fitted_far(scene, light_position, light.near_plane, light.far_plane)
                              : light.far_plane;
  // Each layer's own view-projection (the layout's geometry); layers beyond its own hold the cube's faces.
  // Each matrix is computed once a frame.
  const TexelGeometry& geometry = traits(config.layout).geometry;
  for (int f = 0; f < cube::kFaceCount; ++f)
    u.face_view_proj[size_t(f)] =
        (f < geometry.layers ? geometry.view_projection : layout_geometry::cube_view_projection)(
            f, light_position, light.near_plane, far_plane, range);
  u.camera_position = glm::vec4(cam.position, 1.0f);
  u.light_position = glm::vec4(light_position, far_plane);
  u.light_color = glm::vec4(light.color, light.near_plane);
  const ColourFormat moments_format = colour_format(config.storage, config.depth_format);
  u.knobs =
      glm::vec4(static_cast<float>(injected_work), config.pcf_scale, kPcssLightRadius * config.pcf_scale,
                moments_parameter(config.storage, moments_format, config.moments));
  u.moments_knobs =
      glm::vec4(config.moments.bleed_reduction, moments_distance_scale(config.moments, far_plane),
                std::ldexp(1.0f, is_half(moments_format) ? -11 : -24), 0.0f);
  for (size_t i = 0; i < scene.map_lights.size() && i < u.map_view_proj.size(); ++i) {
    const scene::MapLight& m = scene.map_lights[i];
    const bool spot = m.type == scene::MapLightType::spot;
    u.map_view_proj[i] = map_view_projection(scene, m, frame, range);
    u.map_light[i] = glm::vec4(spot ? m.path.at(frame) : -m.direction, spot ? 1.0f : 2.0f);
    u.map_color[i] = glm::vec4(m.color, m.near_plane);
    u.map_range[i] = glm::vec4(m.far_plane, 0.0f, 0.0f, 0.0f);
  }
  u.lights_info =
      glm::vec4(static_cast<float>(scene.map_lights.size()), scene.has_point_light() ? 1.0f : 0.0f, 0.0f,
                static_cast<float>(config.light_count));
  return u;
}

}  // namespace omnishadow::gpu
