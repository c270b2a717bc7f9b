#include "soltex/render/image.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

namespace soltex {

void write_png(const std::filesystem::path& path, const Image& image) {
  if (!stbi_write_png(path.c_str(), image.width, image.height, 3, image.rgb.data(),
                      image.width * 3)) {
    throw std::runtime_error("cannot write PNG " + path.string());
  }
}

double psnr(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) {
    throw std::invalid_argument("psnr: images differ in size");
  }
  double squared = 0.0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    const double d = static_cast<double>(a.rgb[i]) - static_cast<double>(b.rgb[i]);
    squared += d * d;
  }
  if (squared == 0.0) return std::numeric_limits<double>::infinity();
  const double mse = squared / static_cast<double>(a.rgb.size());
  return 10.0 * std::log10(255.0 * 255.0 / mse);
}

}  // namespace soltex
