#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace soltex {

// An 8-bit sRGB-less RGB image, rows top to bottom.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0) {}
  // Clamps to [0, 1] (NaN to 0) and rounds to 8 bits.
  void set(int x, int y, float r, float g, float b);
  bool operator==(const Image&) const = default;
};

// Writes `image` as PNG; throws std::runtime_error naming the path on failure.
void write_png(const std::filesystem::path& path, const Image& image);

// Peak signal-to-noise ratio in dB over all channels (infinity for identical images).
// Throws std::invalid_argument when the sizes differ.
double psnr(const Image& a, const Image& b);

}  // namespace soltex
