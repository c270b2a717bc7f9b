#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace soltex::gallery {

// An 8-bit RGB image, rows top to bottom.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;

  Image(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0) {}
  void set(int x, int y, float r, float g, float b);
};

// Writes `image` as PNG; throws std::runtime_error naming the path on failure.
void write_png(const std::filesystem::path& path, const Image& image);

}  // namespace soltex::gallery
