#include "soltex/common/text_file.h"

#include <array>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace soltex {

std::optional<std::string> read_at_most(std::istream& in, std::size_t max_bytes) {
  std::string text;
  std::array<char, 1 << 16> chunk;
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (text.size() + got > max_bytes) return std::nullopt;
    text.append(chunk.data(), got);
  }
  return text;
}

namespace {

// Why the last open or read failed, as the C library says it (iostreams keep errno).
std::string cannot_read(const std::string& what, const std::string& path) {
  const int error = errno;
  return "cannot read the " + what + " file '" + path + "'" +
         (error != 0 ? std::string(": ") + std::strerror(error) : std::string());
}

}  // namespace

std::string read_text_file(const std::string& path, const std::string& what) {
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(cannot_read(what, path));
  std::optional<std::string> text = read_at_most(in, kMaxTextFileBytes);
  if (!text) {
    throw std::runtime_error("the " + what + " file '" + path + "' holds more than " +
                             std::to_string(kMaxTextFileBytes) + " bytes, the most it may");
  }
  if (in.bad()) throw std::runtime_error(cannot_read(what, path));
  return std::move(*text);
}

std::string read_trimmed_text_file(const std::string& path, const std::string& what) {
  std::string text = read_text_file(path, what);
  const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!text.empty() && space(text.back())) text.pop_back();
  std::size_t first = 0;
  while (first < text.size() && space(text[first])) ++first;
  text.erase(0, first);
  if (text.empty()) throw std::runtime_error("the " + what + " file '" + path + "' is empty");
  return text;
}

}  // namespace soltex
