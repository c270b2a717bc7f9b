#include "soltex/common/quoted_text.h"

#include <cstdint>
#include <cstdio>
#include <utility>

#include "soltex/common/utf8.h"

namespace soltex {
namespace {

constexpr std::string_view kEllipsis = "\xe2\x80\xa6";  // U+2026

std::string byte_escape(unsigned char byte) {
  char buffer[5];
  std::snprintf(buffer, sizeof buffer, "\\x%02x", byte);
  return buffer;
}

// The character at text[i] as a message shows it, and how many bytes of text it takes.
std::pair<std::string, std::size_t> shown_character(std::string_view text, std::size_t i) {
  const std::size_t length = utf8_sequence_length(text, i);
  const auto byte = static_cast<unsigned char>(text[i]);
  if (length == 0) return {byte_escape(byte), 1};
  if (length > 1) return {std::string(text.substr(i, length)), length};
  switch (byte) {
    case '\n':
      return {"\\n", 1};
    case '\r':
      return {"\\r", 1};
    case '\t':
      return {"\\t", 1};
    case '"':
      return {"\\\"", 1};
    case '\\':
      return {"\\\\", 1};
    default:
      if (byte < 0x20 || byte == 0x7F) return {byte_escape(byte), 1};
      return {std::string(1, text[i]), 1};
  }
}

struct Escaped {
  std::string text;
  bool whole = true;  // false: cut after kQuotedTextBytes bytes of the original
};

Escaped escape_start(std::string_view text) {
  Escaped out;
  for (std::size_t i = 0; i < text.size();) {
    auto [shown, used] = shown_character(text, i);
    if (i + used > kQuotedTextBytes) {
      out.whole = false;
      break;
    }
    out.text += shown;
    i += used;
  }
  return out;
}

std::string length_note(std::string_view text) {
  return " (" + std::to_string(text.size()) + " bytes)";
}

}  // namespace

std::string quoted_text(std::string_view text) {
  const Escaped escaped = escape_start(text);
  if (escaped.whole) return "\"" + escaped.text + "\"";
  return "\"" + escaped.text + std::string(kEllipsis) + "\"" + length_note(text);
}

std::string escaped_text(std::string_view text) {
  const Escaped escaped = escape_start(text);
  if (escaped.whole) return escaped.text;
  return escaped.text + std::string(kEllipsis) + length_note(text);
}

}  // namespace soltex
