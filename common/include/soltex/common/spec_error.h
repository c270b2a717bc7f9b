#pragma once

#include <stdexcept>
#include <string>

namespace soltex {

// A texture spec or volume that breaks a documented bound. The message names the field,
// the offending value and the bound, e.g.
// "marble.turbulence.octave_max = 40: must be in [0, 24]".
class SpecError : public std::invalid_argument {
 public:
  SpecError(std::string field, std::string value, std::string bound);

  const std::string& field() const { return field_; }
  const std::string& value() const { return value_; }
  const std::string& bound() const { return bound_; }

 private:
  std::string field_;
  std::string value_;
  std::string bound_;
};

// A number as a SpecError's value or bound shows it: shortest round-trip digits, and nan, inf
// or -inf spelt out, so that the message names exactly the value that was refused.
std::string spec_number_text(double v);
// A float field (a ramp key) with the digits that read back as that float: 0.2, not the
// 0.20000000298023224 of its double.
std::string spec_number_text(float v);

}  // namespace soltex
