#pragma once

#include <algorithm>
#include <limits>

// double -> float without the undefined behaviour of an out-of-range conversion: values past
// float's range become +-FLT_MAX (NaN stays NaN: both comparisons are false for it). Selects
// rather than branches, so that a loop calling it runs in vector lanes (setup_kernels.cpp).
namespace soltex::raster_internal {

inline float to_float_saturated(double value) {
  constexpr double kMax = std::numeric_limits<float>::max();
  const double low = value < -kMax ? -kMax : value;
  return static_cast<float>(kMax < value ? kMax : low);
}

// A non-negative size (a footprint) as float: past float's range, or NaN (an unbounded
// derivative evaluated as inf - inf), it is +inf.
inline float to_footprint(double size) {
  constexpr double kMax = std::numeric_limits<float>::max();
  return size <= kMax ? static_cast<float>(std::max(size, 0.0))
                      : std::numeric_limits<float>::infinity();
}

}  // namespace soltex::raster_internal
