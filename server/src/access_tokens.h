#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace soltex::server {

// One bearer token a client may present. A named token's callers are one client for the
// per-client limits, wherever they connect from; an unnamed one (the single-token file of old,
// --token) tells nothing about its caller, whose limits then follow its address.
struct AccessToken {
  std::string name;  // empty: unnamed
  std::string secret;
};

// A tokens file: one token per line, `NAME TOKEN` (whitespace between), or `TOKEN` alone for
// an unnamed one (so a file holding just a token, the old format, still works). Blank lines
// and lines starting with '#' are skipped. Two tokens may share a name (rotation: both are
// the same client while the old one is phased out); one secret may not appear twice.
// Throws std::runtime_error naming `origin`, the line and what is wrong with it.
std::vector<AccessToken> parse_access_tokens(std::string_view text, const std::string& origin);

// The file at `path` parsed as above; throws std::runtime_error when it cannot be read.
std::vector<AccessToken> read_access_tokens(const std::string& path);

}  // namespace soltex::server
