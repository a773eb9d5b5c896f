// Reading the case's maps, moments and atlas tiles back for the checks.
#include <cstddef>

#include "backends/common/atlas.h"
#include "backends/common/cube_faces.h"
#include "backends/common/cube_summary.h"
#include "backends/common/frame_uniforms.h"
#include "backends/common/techniques.h"
#include "backends/gl/gl_backend.h"
#include "backends/gl/gl_cube_summary.h"

namespace omnishadow::gl {

void GlBackend::report_light(int light) {
  const float reported = static_cast<float>(light);  // lights_info.z of light 0's block, which lighting binds
  glNamedBufferSubData(frame_ubo_, offsetof(gpu::FrameUniforms, lights_info) + 2 * sizeof(float),
                       sizeof reported, &reported);
  lighting_pass(gpu::LightingVariant::check, lighting_programs_[size_t(gpu::LightingVariant::check)]);
  glFinish();
}

static GLenum moments_format(int channels) {
  return channels == 1 ? GL_RED : channels == 2 ? GL_RG : GL_RGBA;
}

// Layout atlas: light k's six tiles, read as the faces of a cube (row 0 of a tile is t = 0, as a face's).
void GlBackend::read_atlas_faces(int light, float near_plane, float far_plane, Images& img) {
  const atlas::Block& block = shadow_.atlas->lights[size_t(light)];
  const int n = block.face_size;
  const size_t texels = size_t(n) * size_t(n);
  img.cube_size = n;
  const bool depth_stored = !traits(shadow_.storage).colour_checked;
  for (int f = 0; f < cube::kFaceCount; ++f) {
    const atlas::Texel o = atlas::face_origin(block, f);
    auto& face = img.cube_distance[size_t(f)];
    face.resize(texels);
    glGetTextureSubImage(shadow_.stored, 0, o.x, o.y, 0, n, n, 1, depth_stored ? GL_DEPTH_COMPONENT : GL_RED,
                         GL_FLOAT, static_cast<GLsizei>(texels * sizeof(float)), face.data());
    for (size_t i = 0; i < texels; ++i)
      face[i] = cube::stored_to_distance(shadow_.storage, face[i], int(i % size_t(n)), int(i / size_t(n)), n,
                                         near_plane, far_plane, cube::DepthRange::minus_one_to_one);
  }
  if (!shadow_.colour_layers) return;
  img.moment_channels = traits(shadow_.storage).colour_channels;
  for (int f = 0; f < cube::kFaceCount; ++f) {
    const atlas::Texel o = atlas::face_origin(block, f);
    auto& face = img.moments[size_t(f)];
    face.resize(texels * size_t(img.moment_channels));
    glGetTextureSubImage(shadow_.colour, 0, o.x, o.y, 0, n, n, 1, moments_format(img.moment_channels),
                         GL_FLOAT, static_cast<GLsizei>(face.size() * sizeof(float)), face.data());
  }
}

Images GlBackend::read_back_images(CubeReadBack cube_read_back, int light) {
  const LightingTargets& timed = lighting_[size_t(gpu::LightingVariant::timed)];
  const LightingTargets& check = lighting_[size_t(gpu::LightingVariant::check)];
  Images img;
  img.width = check.width;
  img.height = check.height;
  size_t pixels = static_cast<size_t>(img.width) * static_cast<size_t>(img.height);
  img.lit_rgba8.resize(pixels * 4);
  img.timed_lit_rgba8.resize(pixels * 4);
  img.shadow_factor.resize(pixels);
  img.world_position.resize(pixels * 4);
  glGetTextureImage(check.color, 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(img.lit_rgba8.size()),
                    img.lit_rgba8.data());
  glGetTextureImage(timed.color, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                    static_cast<GLsizei>(img.timed_lit_rgba8.size()), img.timed_lit_rgba8.data());
  glGetTextureImage(check.shadow_factor, 0, GL_RED, GL_FLOAT,
                    static_cast<GLsizei>(img.shadow_factor.size() * sizeof(float)), img.shadow_factor.data());
  glGetTextureImage(check.position, 0, GL_RGBA, GL_FLOAT,
                    static_cast<GLsizei>(img.world_position.size() * sizeof(float)),
                    img.world_position.data());

  img.cube_size = shadow_.size;
  size_t texels = static_cast<size_t>(shadow_.size) * static_cast<size_t>(shadow_.size);
  const bool depth_stored = !traits(shadow_.storage).colour_checked;
  // The far the light's map was rendered with (fit_range: per frame).
  const float far_plane = planner_.cube_far(light);
  const float near_plane =
      scene_->has_point_light() ? scene_->point_lights[size_t(light)].near_plane : scene_->light().near_plane;
  img.light_far = far_plane;
  const int first_layer = light * shadow_.layers;
  if (shadow_.atlas) {
    read_atlas_faces(light, near_plane, far_plane, img);  // in full: the summary's compute pass reads layers
    cube_read_back = CubeReadBack::sampled;               // (nothing more to read)
  } else if (cube_read_back == CubeReadBack::sampled) {
    read_cube_summary(summary_program_, shadow_.light_stored_layers[size_t(light)], nearest_sampler_,
                      shadow_.size, img);
    cube::sample_to_distance(img, shadow_.storage, near_plane, far_plane, cube::DepthRange::minus_one_to_one);
  }
  for (int f = 0; f < shadow_.layers && cube_read_back == CubeReadBack::full; ++f) {
    auto& face = img.cube_distance[static_cast<size_t>(f)];
    face.resize(texels);
    glGetTextureSubImage(shadow_.stored, 0, 0, 0, first_layer + f, shadow_.size, shadow_.size, 1,
                         depth_stored ? GL_DEPTH_COMPONENT : GL_RED, GL_FLOAT,
                         static_cast<GLsizei>(texels * sizeof(float)), face.data());
    const size_t n = static_cast<size_t>(shadow_.size);
    for (size_t i = 0; i < texels; ++i)
      face[i] = cube::stored_to_distance(shadow_.storage, face[i], int(i % n), int(i / n), shadow_.size,
                                         near_plane, far_plane, cube::DepthRange::minus_one_to_one);
  }
  if (shadow_.colour_layers && cube_read_back == CubeReadBack::full) {
    img.moment_channels = traits(shadow_.storage).colour_channels;
    for (int f = 0; f < 6; ++f) {
      auto& face = img.moments[static_cast<size_t>(f)];
      face.resize(texels * size_t(img.moment_channels));
      glGetTextureSubImage(shadow_.colour, 0, 0, 0, first_layer + f, shadow_.size, shadow_.size, 1,
                           moments_format(img.moment_channels), GL_FLOAT,
                           static_cast<GLsizei>(face.size() * sizeof(float)), face.data());
    }
  }
  GLenum error = glGetError();
  if (error != GL_NO_ERROR)
    throw std::runtime_error("GL error " + std::to_string(error) + " during read-back");
  if (!scene_->map_lights.empty()) {
    img.map_size = maps_.size;
    const size_t texels = size_t(maps_.size) * size_t(maps_.size);
    for (int l = 0; l < static_cast<int>(scene_->map_lights.size()); ++l) {
      std::vector<float> layer(texels);
      glGetTextureSubImage(maps_.depth, 0, 0, 0, l, maps_.size, maps_.size, 1, GL_DEPTH_COMPONENT, GL_FLOAT,
                           static_cast<GLsizei>(texels * sizeof(float)), layer.data());
      img.map_depth.push_back(std::move(layer));
    }
  }
  return img;
}

}  // namespace omnishadow::gl
