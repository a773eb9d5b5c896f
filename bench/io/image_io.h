#pragma once
// Image files. PNG for looking at (row 0 of the file is the top of the picture); PFM for exact float data
// (the PFM format stores rows bottom-up, which is exactly GL's row order, so float buffers are written
// as-is).

#include <cstdint>
#include <string>
#include <vector>

namespace omnishadow::bench {

// RGBA8 pixels with row 0 at the bottom (GL read-back order), written top-down as PNG.
void write_png_rgba_bottom_up(const std::string& path, int width, int height,
                              const std::vector<uint8_t>& rgba);
// One float channel mapped linearly from [lo, hi] to grey 0..255, clamped; rows written in the order given
// when `flip` is false (cube faces: row 0 = t = 0 at the top), reversed when true (frames: row 0 = bottom).
void write_png_gray(const std::string& path, int width, int height, const std::vector<float>& values,
                    float lo, float hi, bool flip);
void write_png_rgb_top_down(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);
// channels 1 (Pf) or 3 (PF); values.size() == width * height * channels, bottom row first.
void write_pfm(const std::string& path, int width, int height, int channels,
               const std::vector<float>& values);
struct FloatImage {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> values;
};
FloatImage read_pfm(const std::string& path);  // throws std::runtime_error naming the file
struct ByteImage {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<uint8_t> pixels;  // top-down, as the PNG stores them
};
ByteImage read_png(const std::string& path);  // throws std::runtime_error naming the file

}  // namespace omnishadow::bench
