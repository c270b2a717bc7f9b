#include "soltex/common/spec_error.h"

#include <charconv>
#include <cmath>
#include <utility>

namespace soltex {

SpecError::SpecError(std::string field, std::string value, std::string bound)
    : std::invalid_argument(field + " = " + value + ": " + bound),
      field_(std::move(field)),
      value_(std::move(value)),
      bound_(std::move(bound)) {}

namespace {

// The shortest digits that read back as v in its own type: 1e-06, not %.17g's
// 9.9999999999999995e-07; 0.2 for the float 0.2, not its double's 0.20000000298023224.
template <typename Float>
std::string shortest_text(Float v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto written = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, written.ptr);
}

}  // namespace

std::string spec_number_text(double v) {
  return shortest_text(v);
}

std::string spec_number_text(float v) {
  return shortest_text(v);
}

}  // namespace soltex
