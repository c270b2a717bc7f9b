#pragma once

#include <array>

#include "soltex/render/image.h"

namespace soltex::bench {

// How far a frame is from the reference, in three views: PSNR (mean squared error, all
// channels), the worst single channel value, and SSIM (structure, which PSNR misses: a
// slightly blurred texture and a noisy one can have the same PSNR).
struct ImageError {
  double psnr_db = 0.0;          // infinity for identical images
  std::array<int, 3> max_abs{};  // per channel R, G, B, in 8-bit steps
  double ssim = 0.0;             // mean SSIM of the luminance, 8x8 windows; 1 for identical
};

// Throws std::invalid_argument when the sizes differ or the images are smaller than a window.
ImageError image_error(const Image& image, const Image& reference);

// Mean SSIM (Wang, Bovik, Sheikh & Simoncelli 2004) of the Rec. 601 luminance over every 8x8
// window (stride 1, unweighted), with the paper's constants K1 = 0.01, K2 = 0.03, L = 255.
double luminance_ssim(const Image& a, const Image& b);

}  // namespace soltex::bench
