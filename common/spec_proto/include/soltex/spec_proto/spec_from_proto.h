#pragma once

#include "soltex/common/texture_spec.h"
#include "soltex/v1/texture.pb.h"

// Protocol messages <-> validated texture values. from_proto fills absent optional fields
// with the documented defaults, validates, and throws SpecError naming the field on any
// violation (an unset pattern, an unknown enum value, a value out of bounds).
namespace soltex {

TextureSpec from_proto(const v1::TextureSpec& message);
Volume from_proto(const v1::Volume& message);

// The canonical message for a validated value: every field written, defaults included, so
// equal values give equal messages.
v1::TextureSpec to_proto(const TextureSpec& spec);
v1::Volume to_proto(const Volume& volume);

}  // namespace soltex
