#include "http_message_checks.h"

#include <boost/beast/core/string.hpp>
#include <boost/beast/http/field.hpp>
#include <string_view>

namespace soltex::server {
namespace {

namespace http = boost::beast::http;

bool iequals(std::string_view a, std::string_view b) {
  return boost::beast::iequals({a.data(), a.size()}, {b.data(), b.size()});
}

// The last coding of every Transfer-Encoding line together, or empty when there is none.
std::string_view last_transfer_coding(const HttpRequest& request) {
  std::string_view last;
  for (auto [it, end] = request.equal_range(http::field::transfer_encoding); it != end; ++it) {
    std::string_view value(it->value().data(), it->value().size());
    const std::size_t comma = value.rfind(',');
    if (comma != std::string_view::npos) value.remove_prefix(comma + 1);
    last = without_ows(value);
  }
  return last;
}

// uri-host [":" port] (RFC 3986 3.2.2): a name or IPv4 address of unreserved, sub-delims and
// percent-encoded characters, or an IP literal in brackets; empty is allowed (RFC 9112 3.2).
bool valid_host(std::string_view host) {
  for (const char c : host) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    std::string_view("-._~%!$&'()*+,;=:[]").find(c) != std::string_view::npos;
    if (!ok) return false;
  }
  return true;
}

}  // namespace

std::string_view without_ows(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

void without_content(HttpResponse& response) {
  const bool sized = response.result() != http::status::not_modified &&
                     response.result() != http::status::no_content;
  const auto length = response.body().size();
  response.body().clear();
  if (sized) response.content_length(length);
}

std::optional<std::string> framing_problem(const HttpRequest& request) {
  if (request.count(http::field::transfer_encoding) > 0 &&
      !iequals(last_transfer_coding(request), "chunked")) {
    return "Transfer-Encoding must end with chunked in a request (RFC 9112 6.3): its body's "
           "length is otherwise unknown";
  }
  // One credential: with two, which one a proxy or this server would act on is a guess.
  if (const std::size_t tokens = request.count(http::field::authorization); tokens > 1) {
    return "Authorization is given " + std::to_string(tokens) + " times; once";
  }
  const std::size_t hosts = request.count(http::field::host);
  if (hosts > 1) return "Host is given " + std::to_string(hosts) + " times; once (RFC 9112 3.2)";
  if (hosts == 0) {
    if (request.version() >= 11) return "an HTTP/1.1 request needs a Host header (RFC 9112 3.2)";
    return std::nullopt;
  }
  const auto host = request.find(http::field::host)->value();
  if (!valid_host(std::string_view(host.data(), host.size()))) {
    return "Host is not a host name or address with an optional port (RFC 9112 3.2)";
  }
  return std::nullopt;
}

bool expects_continue(const HttpRequest& request) {
  if (request.version() < 11) return false;  // RFC 9110 10.1.1: ignored from HTTP/1.0
  const auto expect = request.find(http::field::expect);
  if (expect == request.end()) return false;
  return iequals(without_ows(std::string_view(expect->value().data(), expect->value().size())),
                 "100-continue");
}

}  // namespace soltex::server
