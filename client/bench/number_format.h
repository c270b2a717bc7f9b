#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace soltex::bench {

// `value` with `decimals` digits after the point ("inf" for infinity, as for identical
// images' PSNR); the reports and the plot print every figure through it.
inline std::string fixed(double value, int decimals) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

}  // namespace soltex::bench
