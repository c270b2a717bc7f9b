// Runtime dispatch of the checker's batch field (checker_kernel.h). Highway compiles this file
// once per target (hwy/foreach_target.h re-includes it); HWY_DYNAMIC_DISPATCH calls the widest
// one the CPU supports, once per batch. The loops are plain per-lane code the compiler runs in
// vector lanes (floor is one rounding instruction from SSE4 on); each lane does the IEEE
// operations of fields::checker() in its order, every branch of filtered_parity() computed and
// then selected, so every target gives the scalar form's bits.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "checker_kernel.cpp"
#include "checker_kernel.h"

#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "box_filtered_waves.h"

HWY_BEFORE_NAMESPACE();
namespace soltex::HWY_NAMESPACE {

// Points per pass: the per-axis lanes live on the stack.
constexpr std::size_t kCheckerChunk = 64;

// waves::square_integral() without its branch: std::max(0.0, v) is 0.0 < v ? v : 0.0.
inline double square_integral_lane(double x) {
  const double periods = std::floor(x * 0.5);
  const double excess = x - 2.0 * periods - 1.0;
  return periods + (0.0 < excess ? excess : 0.0);
}

// waves::filtered_parity(u, w), each case computed and the one it returns selected.
inline double filtered_parity_lane(double u, double w) {
  const bool finite = std::fabs(u) <= std::numeric_limits<double>::max();
  const double whole = std::floor(u);
  const double point = whole - 2.0 * std::floor(whole * 0.5);  // floor_parity(u): 0 or 1
  const double centre = u - 2.0 * std::floor(u / 2.0);         // reduced(u, 2.0)
  const double half = 0.5 * w;
  const double mean =
      (square_integral_lane(centre + half) - square_integral_lane(centre - half)) / w;
  // std::clamp(mean, 0.0, 1.0)
  const double clamped = mean < 0.0 ? 0.0 : (1.0 < mean ? 1.0 : mean);
  const double filtered = w >= waves::kMeanWidth ? 0.5 : clamped;
  const double value = !(w > waves::kPointWidth) ? point : filtered;
  return finite ? value : 0.0;
}

void checker_fields_target(const CheckerParams& c, std::span<const glm::dvec3> points,
                           std::span<const SampleFootprint> footprints, std::span<Texel> out) {
  const int axes = c.three_d ? 3 : 2;
  const std::size_t n = points.size();
  alignas(64) double coordinate[kCheckerChunk], box[kCheckerChunk], sign[kCheckerChunk];
  for (std::size_t begin = 0; begin < n; begin += kCheckerChunk) {
    const std::size_t count = std::min(kCheckerChunk, n - begin);
    std::fill_n(sign, count, 1.0);
    for (int a = 0; a < axes; ++a) {
      const double size = c.size[a];
      // Copied out of the interleaved points first, so that the divisions too run in lanes.
      for (std::size_t i = 0; i < count; ++i) {
        coordinate[i] = points[begin + i][a];
        box[i] = footprints[begin + i].box[a];
      }
      for (std::size_t i = 0; i < count; ++i) {
        const double u = c.offset + coordinate[i] / size;
        const double w = box[i] / size;
        sign[i] *= 1.0 - 2.0 * filtered_parity_lane(u, w);
      }
    }
    for (std::size_t i = 0; i < count; ++i) {
      out[begin + i].field = static_cast<float>(0.5 * (1.0 - sign[i]));
    }
  }
}

}  // namespace soltex::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex {

HWY_EXPORT(checker_fields_target);

void checker_fields(const CheckerParams& c, std::span<const glm::dvec3> points,
                    std::span<const SampleFootprint> footprints, std::span<Texel> out) {
  HWY_DYNAMIC_DISPATCH(checker_fields_target)(c, points, footprints, out);
}

}  // namespace soltex
#endif
