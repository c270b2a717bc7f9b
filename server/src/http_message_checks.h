#pragma once

#include <optional>
#include <string>

#include "http_request_handler.h"

namespace soltex::server {

// What Beast's parser accepts but HTTP/1.1 does not (RFC 9112): a Transfer-Encoding whose
// last coding is not chunked (the body's end is then unknown, and reading on would take the
// rest as another request: answered 400 and the connection closed), and a missing, repeated or
// malformed Host. Returns the problem, named, or nothing.
std::optional<std::string> framing_problem(const HttpRequest& request);

// Whether the client waits for "100 Continue" before sending its body (HTTP/1.1 only).
bool expects_continue(const HttpRequest& request);

}  // namespace soltex::server
