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

std::string spec_number_text(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  // The shortest digits that read back as v: 1e-06, not %.17g's 9.9999999999999995e-07.
  char buffer[32];
  const auto written = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, written.ptr);
}

std::string spec_number_text(float v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto written = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, written.ptr);
}

}  // namespace soltex
