#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace soltex {

// How much of a client's string a message shows: enough to recognise it, and few enough that
// the message stays far below gRPC's metadata limit however long the string sent was. Every
// name the limits allow (64 bytes) is shown whole.
inline constexpr std::size_t kQuotedTextBytes = 64;

// A client-supplied string as an error message shows it, in double quotes. Control characters,
// quotes, backslashes and bytes that are not UTF-8 are escaped (\n, \", \\, \x00), and so are
// the C1 controls, line separators and bidirectional controls (\u202e), so that what was sent
// is visible and cannot end, reorder or forge the message; past kQuotedTextBytes it is cut,
// with its whole length after: "abc…" (10000 bytes).
std::string quoted_text(std::string_view text);

// The same without the quotes, for a name inside a field: graph.nodes[abc… (10000 bytes)].
std::string escaped_text(std::string_view text);

}  // namespace soltex
