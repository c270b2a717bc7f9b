#pragma once

#include <cstddef>
#include <string_view>

namespace soltex {

// The length of the well-formed UTF-8 sequence that starts at text[i] (no overlong forms,
// surrogates or code points past U+10FFFF), or 0 where none does. i < text.size().
std::size_t utf8_sequence_length(std::string_view text, std::size_t i);

// Whether all of text is well-formed UTF-8, as protobuf requires of a string field.
bool is_utf8(std::string_view text);

}  // namespace soltex
