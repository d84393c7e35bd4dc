// Application layer: used by tools/ and viz/, never by the library modules.
// PNG output (8-bit RGB or RGBA; our encoder over zlib, in parallel), written atomically; input
// through libpng. The bytes depend only on the
// pixels (no time stamps), so identical images give identical files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace iaa::app {

/// An 8-bit image, rows from the top, `channels` (3 = RGB, 4 = RGBA) bytes per pixel.
struct Image8 {
  int width = 0, height = 0, channels = 3;
  std::vector<std::uint8_t> data;

  Image8() = default;
  Image8(int w, int h, int c) : width(w), height(h), channels(c), data(std::size_t(w) * h * c, 0) {}
  std::uint8_t* at(int x, int y) { return &data[(std::size_t(y) * width + x) * channels]; }
  const std::uint8_t* at(int x, int y) const {
    return &data[(std::size_t(y) * width + x) * channels];
  }
};

/// Writes the image as PNG; throws iaa::Error naming the path on failure.
void write_png(const std::string& path, const Image8& image);

/// Reads an 8-bit PNG (converted to RGB or RGBA); throws iaa::Error on failure.
Image8 read_png(const std::string& path);

/// Converts a linear value in [0, 1] to an 8-bit sRGB-ish value (gamma 2.2), clamping.
std::uint8_t to_byte(double v);

}  // namespace iaa::app
