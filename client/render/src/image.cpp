#include "soltex/render/image.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

namespace soltex {

void write_png(const std::filesystem::path& path, const Image& image) {
  errno = 0;
  if (!stbi_write_png(path.c_str(), image.width, image.height, 3, image.rgb.data(),
                      image.width * 3)) {
    // stb opens the file with fopen, which says why it could not.
    const int error = errno;
    throw std::runtime_error("cannot write PNG " + path.string() +
                             (error != 0 ? std::string(": ") + std::strerror(error) : ""));
  }
}

Image box_downsample(const Image& image, int k) {
  if (k <= 1) return image;
  if (image.width % k != 0 || image.height % k != 0) {
    throw std::invalid_argument("box_downsample: " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + " is not a multiple of " +
                                std::to_string(k));
  }
  Image out(image.width / k, image.height / k);
  const unsigned count = static_cast<unsigned>(k * k);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      std::array<unsigned, 3> sum{};
      for (int sy = 0; sy < k; ++sy) {
        for (int sx = 0; sx < k; ++sx) {
          const uint8_t* rgb = image.pixel(x * k + sx, y * k + sy);
          for (std::size_t c = 0; c < 3; ++c) sum[c] += rgb[c];
        }
      }
      uint8_t* px = out.pixel(x, y);
      for (std::size_t c = 0; c < 3; ++c)
        px[c] = static_cast<uint8_t>((2 * sum[c] + count) / (2 * count));
    }
  }
  return out;
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
