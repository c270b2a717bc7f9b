#pragma once

#include <cstddef>
#include <istream>
#include <optional>
#include <string>

namespace soltex {

// The most a text file the tools read whole (a scene, a MaterialX document, a tokens file, a
// certificate) may hold: far above any real one, and a device such as /dev/zero or a
// mistaken multi-gigabyte file is refused before it fills memory.
inline constexpr std::size_t kMaxTextFileBytes = std::size_t{64} << 20;

// All of `in` if it holds at most `max_bytes`; nullopt when it holds more (then `in` is left
// somewhere past byte max_bytes, at most a 64 KiB read further on).
std::optional<std::string> read_at_most(std::istream& in, std::size_t max_bytes);

// The whole file, at most kMaxTextFileBytes. Throws std::runtime_error "cannot read the
// <what> file '<path>'", or naming the bound.
std::string read_text_file(const std::string& path, const std::string& what);

// The file without surrounding whitespace (a trailing newline is not part of a token or a
// secret). Throws std::runtime_error as above, or when nothing is left.
std::string read_trimmed_text_file(const std::string& path, const std::string& what);

}  // namespace soltex
