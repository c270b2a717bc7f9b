#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "http_request_handler.h"

namespace soltex::server {

// What Beast's parser accepts but HTTP/1.1 does not (RFC 9112): a Transfer-Encoding whose
// last coding is not chunked (the body's end is then unknown, and reading on would take the
// rest as another request: answered 400 and the connection closed), and a missing, repeated or
// malformed Host, and more than one Authorization. Returns the problem, named, or nothing.
std::optional<std::string> framing_problem(const HttpRequest& request);

// `text` without the optional whitespace (spaces and tabs) around a field value or list item.
std::string_view without_ows(std::string_view text);

// A response to HEAD: no content, and the length a GET's content would have, where the status
// has content at all (RFC 9110 9.3.2, 8.6).
void without_content(HttpResponse& response);

// Whether the client waits for "100 Continue" before sending its body (HTTP/1.1 only).
bool expects_continue(const HttpRequest& request);

}  // namespace soltex::server
