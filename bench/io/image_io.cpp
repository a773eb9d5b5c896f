#include "bench/io/image_io.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image_write.h>
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#include "bench/io/file_io.h"

namespace omnishadow::bench {
namespace {

void write_png(const std::string& path, int width, int height, int components, const uint8_t* data,
               int stride) {
  std::string bytes;
  auto sink = [](void* context, void* chunk, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(chunk), static_cast<size_t>(size));
  };
  if (!stbi_write_png_to_func(sink, &bytes, width, height, components, data, stride))
    throw std::runtime_error("cannot encode PNG " + path);
  write_file_atomic(path, bytes);
}

}  // namespace

void write_png_rgba_bottom_up(const std::string& path, int width, int height,
                              const std::vector<uint8_t>& rgba) {
  int stride = width * 4;
  // A negative stride walks the rows from the last (top of the picture) to the first.
  write_png(path, width, height, 4,
            rgba.data() + static_cast<size_t>(height - 1) * static_cast<size_t>(stride), -stride);
}

void write_png_gray(const std::string& path, int width, int height, const std::vector<float>& values,
                    float lo, float hi, bool flip) {
  std::vector<uint8_t> grey(values.size());
  float scale = hi > lo ? 255.0f / (hi - lo) : 0.0f;
  for (size_t i = 0; i < values.size(); ++i)
    grey[i] = static_cast<uint8_t>(std::clamp((values[i] - lo) * scale, 0.0f, 255.0f) + 0.5f);
  if (flip)
    write_png(path, width, height, 1,
              grey.data() + static_cast<size_t>(height - 1) * static_cast<size_t>(width), -width);
  else
    write_png(path, width, height, 1, grey.data(), width);
}

void write_png_rgb_top_down(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  write_png(path, width, height, 3, rgb.data(), width * 3);
}

void write_pfm(const std::string& path, int width, int height, int channels,
               const std::vector<float>& values) {
  if (channels != 1 && channels != 3) throw std::invalid_argument("PFM holds 1 or 3 channels");
  // Negative scale = little-endian floats, which is what this machine (x86-64, aarch64) stores.
  std::string header = std::string(channels == 3 ? "PF" : "Pf") + "\n" + std::to_string(width) + " " +
                       std::to_string(height) + "\n-1.0\n";
  std::string bytes = header;
  bytes.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
  write_file_atomic(path, bytes);
}

FloatImage read_pfm(const std::string& path) {
  std::string bytes = read_file(path);
  FloatImage img;
  char kind[3] = {0};
  double scale = 0;
  int consumed = 0;
  if (std::sscanf(bytes.c_str(), "%2s %d %d %lf%n", kind, &img.width, &img.height, &scale, &consumed) != 4 ||
      (std::strcmp(kind, "PF") != 0 && std::strcmp(kind, "Pf") != 0) || img.width <= 0 || img.height <= 0 ||
      scale >= 0)
    throw std::runtime_error(path + ": not a little-endian PFM file");
  img.channels = kind[1] == 'F' ? 3 : 1;
  size_t offset = static_cast<size_t>(consumed) + 1;  // one whitespace byte ends the header
  size_t count =
      static_cast<size_t>(img.width) * static_cast<size_t>(img.height) * static_cast<size_t>(img.channels);
  if (bytes.size() < offset + count * sizeof(float)) throw std::runtime_error(path + ": truncated PFM file");
  img.values.resize(count);
  std::memcpy(img.values.data(), bytes.data() + offset, count * sizeof(float));
  return img;
}

ByteImage read_png(const std::string& path) {
  std::string bytes = read_file(path);
  ByteImage img;
  unsigned char* data =
      stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()),
                            static_cast<int>(bytes.size()), &img.width, &img.height, &img.channels, 0);
  if (!data) throw std::runtime_error(path + ": not a readable PNG (" + stbi_failure_reason() + ")");
  img.pixels.assign(data, data + static_cast<size_t>(img.width) * img.height * img.channels);
  stbi_image_free(data);
  return img;
}

}  // namespace omnishadow::bench
