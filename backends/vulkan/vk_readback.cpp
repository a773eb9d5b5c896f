// Reading the case's maps, moments and atlas tiles back for the checks.
#include <cstddef>
#include <cstring>
#include <glm/gtc/packing.hpp>

#include "backends/common/atlas.h"
#include "backends/common/cube_faces.h"
#include "backends/common/cube_summary.h"
#include "backends/common/frame_uniforms.h"
#include "backends/common/storage_filter_tables.h"
#include "backends/common/techniques.h"
#include "backends/vulkan/vk_backend.h"

namespace omnishadow::vk {

namespace {

// Texels as read back (D16, X8_D24 or 32-bit float: depth or R32F) to floats; UNORM depth to [0, 1].
std::vector<float> decode_texels(VkFormat format, const uint8_t* src, size_t count) {
  std::vector<float> out(count);
  for (size_t i = 0; i < count; ++i) {
    if (format == VK_FORMAT_D16_UNORM) {
      uint16_t x;
      std::memcpy(&x, src + 2 * i, 2);
      out[i] = static_cast<float>(x) / 65535.0f;
    } else if (format == VK_FORMAT_X8_D24_UNORM_PACK32) {
      uint32_t x;
      std::memcpy(&x, src + 4 * i, 4);
      out[i] = static_cast<float>(x & 0xFFFFFFu) / 16777215.0f;
    } else {
      std::memcpy(&out[i], src + 4 * i, 4);
    }
  }
  return out;
}

}  // namespace

// The blurred moments as floats, `moment_channels` a texel (binary16 widened exactly).
void VkBackend::read_moments(Images& img, int light) {
  const int channels = traits(shadow_.storage).colour_channels;
  const bool half = is_half(colour_format(shadow_.storage, config_->depth_format));
  const uint32_t texel_bytes = uint32_t(channels) * (half ? 2u : 4u);
  const std::vector<uint8_t> bytes = read_image(*ctx_, shadow_.color, VK_IMAGE_LAYOUT_GENERAL, texel_bytes);
  const size_t edge = shadow_.atlas ? size_t(shadow_.atlas->lights[size_t(light)].face_size) : shadow_.size;
  const size_t values = edge * edge * size_t(channels);
  img.moment_channels = channels;
  for (size_t f = 0; f < 6; ++f) {
    std::vector<float>& face = img.moments[f];
    face.resize(values);
    const uint8_t* src = bytes.data() + (size_t(light) * shadow_.layers + f) * values * (half ? 2 : 4);
    std::vector<uint8_t> tile;  // layout atlas: the face's rows cut from the layer
    if (shadow_.atlas) {
      const atlas::Block& block = shadow_.atlas->lights[size_t(light)];
      const atlas::Texel o = atlas::face_origin(block, int(f));
      const size_t row = size_t(block.face_size) * texel_bytes;
      tile.resize(row * size_t(block.face_size));
      for (int y = 0; y < block.face_size; ++y)
        std::memcpy(tile.data() + size_t(y) * row,
                    bytes.data() + (size_t(o.y + y) * shadow_.color.width + size_t(o.x)) * texel_bytes, row);
      src = tile.data();
    }
    for (size_t i = 0; i < values; ++i) {
      if (half) {
        uint16_t h;
        std::memcpy(&h, src + 2 * i, 2);
        face[i] = glm::unpackHalf1x16(h);
      } else {
        std::memcpy(&face[i], src + 4 * i, 4);
      }
    }
  }
}

void VkBackend::report_light(int light) {
  const float reported = static_cast<float>(light);  // lights_info.z of light 0's block, which lighting binds
  std::memcpy(static_cast<uint8_t*>(frame_uniforms_.mapped) + offsetof(gpu::FrameUniforms, lights_info) +
                  2 * sizeof(float),
              &reported, sizeof reported);
  uint64_t draws = 0;
  record_lighting(command_buffers_[1], gpu::LightingVariant::check, false, draws);
  ctx_->submit(command_buffers_[1]);
  ctx_->wait();
}

// Layout atlas: the whole layer read back, light k's six tiles cut from it as the faces of a cube (row 0 of a
// tile is t = 0, as a face's).
void VkBackend::read_atlas_faces(Images& img, int light, float near_plane, float far_plane) {
  const Image& stored = shadow_.stored();
  const uint32_t texel_bytes = stored.format == VK_FORMAT_D16_UNORM ? 2 : 4;
  const std::vector<uint8_t> bytes =
      read_image(*ctx_, stored, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, texel_bytes);
  const atlas::Block& block = shadow_.atlas->lights[size_t(light)];
  const int n = block.face_size;
  img.cube_size = n;
  for (int f = 0; f < cube::kFaceCount; ++f) {
    const atlas::Texel o = atlas::face_origin(block, f);
    std::vector<uint8_t> rows(size_t(n) * size_t(n) * texel_bytes);
    for (int y = 0; y < n; ++y)
      std::memcpy(rows.data() + size_t(y) * size_t(n) * texel_bytes,
                  bytes.data() + (size_t(o.y + y) * stored.width + size_t(o.x)) * texel_bytes,
                  size_t(n) * texel_bytes);
    auto& face = img.cube_distance[size_t(f)];
    face = decode_texels(stored.format, rows.data(), size_t(n) * size_t(n));
    for (size_t i = 0; i < face.size(); ++i)
      face[i] = cube::stored_to_distance(shadow_.storage, face[i], int(i % size_t(n)), int(i / size_t(n)), n,
                                         near_plane, far_plane, cube::DepthRange::zero_to_one);
  }
}

Images VkBackend::read_back_images(CubeReadBack cube_read_back, int light) {
  const LightingTargets& check = lighting_[size_t(gpu::LightingVariant::check)];
  Images img;
  img.width = static_cast<int>(check.width);
  img.height = static_cast<int>(check.height);
  const VkImageLayout ready = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  img.lit_rgba8 = read_image(*ctx_, check.color, ready, 4);
  img.timed_lit_rgba8 = read_image(*ctx_, lighting_[size_t(gpu::LightingVariant::timed)].color, ready, 4);
  auto floats = [](const std::vector<uint8_t>& bytes) {
    std::vector<float> out(bytes.size() / sizeof(float));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(float));
    return out;
  };
  img.shadow_factor = floats(read_image(*ctx_, check.shadow_factor, ready, 4));
  img.world_position = floats(read_image(*ctx_, check.position, ready, 16));

  img.cube_size = static_cast<int>(shadow_.size);
  const Image& stored = shadow_.stored();
  // The far the light's map was rendered with (fit_range: per frame).
  const float far_plane = planner_.cube_far(light);
  const float near_plane =
      scene_->has_point_light() ? scene_->point_lights[size_t(light)].near_plane : scene_->light().near_plane;
  img.light_far = far_plane;
  if (cube_read_back == CubeReadBack::sampled && !shadow_.atlas) {
    summarizer_->read(stored, nearest_sampler_, shadow_.size, img, uint32_t(light) * shadow_.layers);
    cube::sample_to_distance(img, shadow_.storage, near_plane, far_plane, cube::DepthRange::zero_to_one);
  }
  const uint32_t texel_bytes = stored.format == VK_FORMAT_D16_UNORM ? 2 : 4;
  std::vector<uint8_t> bytes;
  if (shadow_.atlas) {  // in full: the summary's compute pass reads layers, an atlas's faces are tiles
    read_atlas_faces(img, light, near_plane, far_plane);
    if (blur_) read_moments(img, light);
    cube_read_back = CubeReadBack::sampled;  // nothing more to read
  }
  if (cube_read_back == CubeReadBack::full)
    bytes = read_image(*ctx_, stored, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, texel_bytes);
  const size_t texels = size_t(shadow_.size) * shadow_.size;
  for (size_t f = 0; f < shadow_.layers && !bytes.empty(); ++f) {
    auto& face = img.cube_distance[f];
    const size_t layer = size_t(light) * shadow_.layers + f;
    face = decode_texels(stored.format, bytes.data() + layer * texels * texel_bytes, texels);
    for (size_t i = 0; i < texels; ++i)
      face[i] =
          cube::stored_to_distance(shadow_.storage, face[i], int(i % shadow_.size), int(i / shadow_.size),
                                   int(shadow_.size), near_plane, far_plane, cube::DepthRange::zero_to_one);
  }
  if (blur_ && cube_read_back == CubeReadBack::full) read_moments(img, light);
  if (!scene_->map_lights.empty()) {
    img.map_size = static_cast<int>(maps_.size);
    img.map_depth_zero_to_one = true;
    const uint32_t map_bytes = maps_.depth.format == VK_FORMAT_D16_UNORM ? 2 : 4;
    std::vector<uint8_t> all =
        read_image(*ctx_, maps_.depth, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, map_bytes);
    const size_t map_texels = size_t(maps_.size) * maps_.size;
    for (size_t l = 0; l < scene_->map_lights.size(); ++l)
      img.map_depth.push_back(
          decode_texels(maps_.depth.format, all.data() + l * map_texels * map_bytes, map_texels));
  }
  return img;
}

}  // namespace omnishadow::vk
