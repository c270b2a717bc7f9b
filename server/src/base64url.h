#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace soltex::server {

// base64url (RFC 4648 section 5) without padding: a registration rides in a URL query as this.
std::string base64url_encode(std::string_view bytes);

// nullopt for a character outside the alphabet, padding, or a length no encoding has
// (a remainder of 1 mod 4), or non-zero bits left over in the last character.
std::optional<std::string> base64url_decode(std::string_view text);

}  // namespace soltex::server
