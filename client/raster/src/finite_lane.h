#pragma once

#include <cmath>
#include <limits>

namespace soltex::raster_internal {

// std::isfinite written as a compare, which a lane loop keeps in vector registers (isfinite
// is a classification the compiler does not vectorise).
template <typename Real>
inline bool finite_lane(Real v) {
  return std::fabs(v) <= std::numeric_limits<Real>::max();
}

}  // namespace soltex::raster_internal
