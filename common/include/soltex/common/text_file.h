#pragma once

#include <string>

namespace soltex {

// The whole file. Throws std::runtime_error "cannot read the <what> file '<path>'".
std::string read_text_file(const std::string& path, const std::string& what);

// The file without surrounding whitespace (a trailing newline is not part of a token or a
// secret). Throws std::runtime_error as above, or when nothing is left.
std::string read_trimmed_text_file(const std::string& path, const std::string& what);

}  // namespace soltex
