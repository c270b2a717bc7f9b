#include "soltex/common/spec_error.h"

#include <utility>

namespace soltex {

SpecError::SpecError(std::string field, std::string value, std::string bound)
    : std::invalid_argument(field + " = " + value + ": " + bound),
      field_(std::move(field)),
      value_(std::move(value)),
      bound_(std::move(bound)) {}

}  // namespace soltex
