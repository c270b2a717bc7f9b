// libFuzzer target for soltexd's HTTP request path: the bytes are read as an HTTP/1.1 request
// by Beast's parser with the daemon's bounds, then routed by route_request() as the daemon
// routes it; any method and target are also routed directly. Whatever comes in, the route is
// either refused with a 4xx status (or 501 for CONNECT, which soltexd does not implement) and a
// message, or names a resource whose fields keep their
// bounds, and a ?spec= value decodes as base64url only where it is the one spelling of its bytes.

#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/http.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "base64url.h"
#include "http_router.h"

namespace {

namespace http = boost::beast::http;
using soltex::server::Route;
using soltex::server::RouteKind;

void check(bool condition) {
  if (!condition) std::abort();
}

void check_route(std::string_view method, std::string_view target) {
  const Route route = soltex::server::route_request(method, target);
  if (route.kind == RouteKind::refused) {
    check((route.status >= 400 && route.status < 500) ||
          (route.status == 501 && method == "CONNECT"));
    check(!route.message.empty());
    check(route.status != 405 || !route.allow.empty());
    return;
  }
  check(route.level <= soltex::server::kMaxPathInteger);
  check(route.x <= soltex::server::kMaxPathInteger);
  check(route.y <= soltex::server::kMaxPathInteger);
  check(route.z <= soltex::server::kMaxPathInteger);
  check(route.spec.size() <= soltex::server::kMaxSpecParameterBytes);
  if (!route.spec.empty()) {
    const auto bytes = soltex::server::base64url_decode(route.spec);
    if (bytes) check(soltex::server::base64url_encode(*bytes) == route.spec);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);

  // As a whole request off the wire.
  http::request_parser<http::string_body> parser;
  parser.header_limit(16384);
  parser.body_limit(4u << 20);
  parser.eager(true);
  boost::beast::error_code ec;
  parser.put(boost::asio::buffer(data, size), ec);
  if (!ec && parser.is_header_done()) {
    const auto& request = parser.get();
    check_route(std::string_view(request.method_string().data(), request.method_string().size()),
                std::string_view(request.target().data(), request.target().size()));
  }

  // As a target alone, for each method the routes know.
  for (const char* method : {"GET", "HEAD", "POST", "OPTIONS", "PUT", "CONNECT"}) {
    check_route(method, text);
  }

  // base64url both ways: what decodes re-encodes to the same text; what encodes decodes back.
  if (const auto bytes = soltex::server::base64url_decode(text)) {
    check(soltex::server::base64url_encode(*bytes) == text);
  }
  check(soltex::server::base64url_decode(soltex::server::base64url_encode(text)) ==
        std::string(text));
  return 0;
}
