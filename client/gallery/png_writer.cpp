#include "png_writer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

namespace soltex::gallery {
namespace {

// Clamp before quantizing: 1.0000001 must become 255, NaN becomes 0.
uint8_t to_byte(float v) {
  if (!(v > 0.0f)) return 0;
  return static_cast<uint8_t>(std::lround(std::min(v, 1.0f) * 255.0f));
}

}  // namespace

void Image::set(int x, int y, float r, float g, float b) {
  uint8_t* px = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
  px[0] = to_byte(r);
  px[1] = to_byte(g);
  px[2] = to_byte(b);
}

void write_png(const std::filesystem::path& path, const Image& image) {
  if (!stbi_write_png(path.c_str(), image.width, image.height, 3, image.rgb.data(),
                      image.width * 3)) {
    throw std::runtime_error("cannot write PNG " + path.string());
  }
}

}  // namespace soltex::gallery
