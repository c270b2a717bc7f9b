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

// The code point of the well-formed `length`-byte sequence at text[i] (length 2 to 4).
uint32_t code_point(std::string_view text, std::size_t i, std::size_t length) {
  static constexpr unsigned char kLeadBits[] = {0, 0, 0x1F, 0x0F, 0x07};
  uint32_t c = static_cast<unsigned char>(text[i]) & kLeadBits[length];
  for (std::size_t k = 1; k < length; ++k) {
    c = (c << 6) | (static_cast<unsigned char>(text[i + k]) & 0x3Fu);
  }
  return c;
}

// Characters that are valid UTF-8 and still change how the rest of a line reads: the C1
// controls (U+0080 to U+009F, which some terminals obey), the line and paragraph separators,
// and the bidirectional marks, embeddings, overrides and isolates (which reorder what follows,
// so that a message could show other text than it holds).
bool hides_or_reorders(uint32_t c) {
  return (c >= 0x80 && c <= 0x9F) || c == 0x061C || c == 0x200E || c == 0x200F ||
         (c >= 0x2028 && c <= 0x202E) || (c >= 0x2066 && c <= 0x2069);
}

std::string code_point_escape(uint32_t c) {
  char buffer[12];
  std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(c));
  return buffer;
}

// The character at text[i] as a message shows it, and how many bytes of text it takes.
std::pair<std::string, std::size_t> shown_character(std::string_view text, std::size_t i) {
  const std::size_t length = utf8_sequence_length(text, i);
  const auto byte = static_cast<unsigned char>(text[i]);
  if (length == 0) return {byte_escape(byte), 1};
  if (length > 1) {
    const uint32_t c = code_point(text, i, length);
    if (hides_or_reorders(c)) return {code_point_escape(c), length};
    return {std::string(text.substr(i, length)), length};
  }
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
