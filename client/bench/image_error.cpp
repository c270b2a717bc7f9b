#include "image_error.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <vector>

namespace soltex::bench {
namespace {

constexpr int kWindow = 8;

std::vector<double> luminance(const Image& image) {
  std::vector<double> y(static_cast<std::size_t>(image.width) * image.height);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const uint8_t* px = &image.rgb[3 * i];
    y[i] = 0.299 * px[0] + 0.587 * px[1] + 0.114 * px[2];
  }
  return y;
}

// Summed-area table with a zero first row and column: any window's sum in four reads, so
// every 8x8 window costs the same as a 1x1 one.
class SummedArea {
 public:
  SummedArea(int width, int height) : stride_(width + 1), sums_((width + 1) * (height + 1), 0.0) {}

  void build(int width, int height, const auto& value_at) {
    for (int y = 0; y < height; ++y) {
      double row = 0.0;
      for (int x = 0; x < width; ++x) {
        row += value_at(static_cast<std::size_t>(y) * width + x);
        at(x + 1, y + 1) = at(x + 1, y) + row;
      }
    }
  }
  double window(int x, int y, int size) const {
    return at(x + size, y + size) - at(x, y + size) - at(x + size, y) + at(x, y);
  }

 private:
  double& at(int x, int y) { return sums_[static_cast<std::size_t>(y) * stride_ + x]; }
  double at(int x, int y) const { return sums_[static_cast<std::size_t>(y) * stride_ + x]; }

  int stride_;
  std::vector<double> sums_;
};

}  // namespace

double luminance_ssim(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) {
    throw std::invalid_argument("image_error: images differ in size");
  }
  if (a.width < kWindow || a.height < kWindow) {
    throw std::invalid_argument("image_error: images smaller than an 8x8 window");
  }
  const int w = a.width, h = a.height;
  const std::vector<double> ya = luminance(a), yb = luminance(b);
  SummedArea sa(w, h), sb(w, h), saa(w, h), sbb(w, h), sab(w, h);
  sa.build(w, h, [&](std::size_t i) { return ya[i]; });
  sb.build(w, h, [&](std::size_t i) { return yb[i]; });
  saa.build(w, h, [&](std::size_t i) { return ya[i] * ya[i]; });
  sbb.build(w, h, [&](std::size_t i) { return yb[i] * yb[i]; });
  sab.build(w, h, [&](std::size_t i) { return ya[i] * yb[i]; });
  constexpr double kC1 = (0.01 * 255.0) * (0.01 * 255.0);
  constexpr double kC2 = (0.03 * 255.0) * (0.03 * 255.0);
  constexpr double kN = kWindow * kWindow;
  double total = 0.0;
  for (int y = 0; y + kWindow <= h; ++y) {
    for (int x = 0; x + kWindow <= w; ++x) {
      const double ma = sa.window(x, y, kWindow) / kN;
      const double mb = sb.window(x, y, kWindow) / kN;
      const double va = saa.window(x, y, kWindow) / kN - ma * ma;
      const double vb = sbb.window(x, y, kWindow) / kN - mb * mb;
      const double cov = sab.window(x, y, kWindow) / kN - ma * mb;
      total += ((2.0 * ma * mb + kC1) * (2.0 * cov + kC2)) /
               ((ma * ma + mb * mb + kC1) * (va + vb + kC2));
    }
  }
  return total / (static_cast<double>(w - kWindow + 1) * (h - kWindow + 1));
}

ImageError image_error(const Image& image, const Image& reference) {
  ImageError error;
  error.psnr_db = psnr(image, reference);  // checks the sizes
  for (std::size_t i = 0; i < image.rgb.size(); ++i) {
    int& worst = error.max_abs[i % 3];
    worst = std::max(worst, std::abs(int{image.rgb[i]} - int{reference.rgb[i]}));
  }
  error.ssim = luminance_ssim(image, reference);
  return error;
}

}  // namespace soltex::bench
