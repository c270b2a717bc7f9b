#pragma once

#include <algorithm>
#include <cstddef>
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
  // Clamps to [0, 1] (NaN to 0) and rounds to 8 bits. Inline: the renderers call it per pixel.
  void set(int x, int y, float r, float g, float b) {
    uint8_t* px = pixel(x, y);
    px[0] = to_byte(r);
    px[1] = to_byte(g);
    px[2] = to_byte(b);
  }
  uint8_t* pixel(int x, int y) {
    return &rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                 static_cast<std::size_t>(x)) *
                3];
  }
  const uint8_t* pixel(int x, int y) const { return const_cast<Image*>(this)->pixel(x, y); }
  bool operator==(const Image&) const = default;

 private:
  static uint8_t to_byte(float v) {
    if (!(v > 0.0f)) return 0;                                       // also NaN
    return static_cast<uint8_t>(std::min(v, 1.0f) * 255.0f + 0.5f);  // round half up
  }
};

// Each k x k block of `image` averaged into one pixel (the 8-bit values averaged, rounded half
// up); `image`'s sizes must be multiples of k.
Image box_downsample(const Image& image, int k);

// Writes `image` as PNG; throws std::runtime_error naming the path on failure.
void write_png(const std::filesystem::path& path, const Image& image);

// Peak signal-to-noise ratio in dB over all channels (infinity for identical images).
// Throws std::invalid_argument when the sizes differ.
double psnr(const Image& a, const Image& b);

}  // namespace soltex
