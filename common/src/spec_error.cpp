#include "soltex/common/spec_error.h"

#include <cmath>
#include <cstdio>
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
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

}  // namespace soltex
