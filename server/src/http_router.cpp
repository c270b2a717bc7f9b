#include "http_router.h"

#include <optional>
#include <vector>

namespace soltex::server {
namespace {

constexpr std::string_view kRoutes =
    "POST /v1/textures, GET /v1/textures/{id}, GET /v1/textures/{id}/bricks/{level}/{x}/{y}/{z}";

Route refuse(unsigned status, std::string message, std::string allow = {}) {
  Route route;
  route.kind = RouteKind::refused;
  route.status = status;
  route.message = std::move(message);
  route.allow = std::move(allow);
  return route;
}

// Shown in messages: at most 64 bytes of what the client sent, non-printable bytes as '?'.
std::string quoted(std::string_view text) {
  std::string out = "'";
  for (const char c : text.substr(0, 64)) out += (c >= 0x20 && c < 0x7f) ? c : '?';
  if (text.size() > 64) out += "...";
  return out + "'";
}

std::vector<std::string_view> split(std::string_view text, char separator) {
  std::vector<std::string_view> parts;
  while (true) {
    const std::size_t at = text.find(separator);
    parts.push_back(text.substr(0, at));
    if (at == std::string_view::npos) return parts;
    text.remove_prefix(at + 1);
  }
}

std::optional<uint64_t> parse_texture_id(std::string_view text) {
  if (text.size() != 16) return std::nullopt;
  uint64_t id = 0;
  for (const char c : text) {
    int digit = 0;
    if (c >= '0' && c <= '9') {
      digit = c - '0';
    } else if (c >= 'a' && c <= 'f') {
      digit = c - 'a' + 10;
    } else {
      return std::nullopt;  // upper case too: one spelling per id keeps one cache entry
    }
    id = (id << 4) | static_cast<uint64_t>(digit);
  }
  return id;
}

// Plain decimal without sign or leading zeros (one spelling per brick, one cache entry).
std::optional<uint32_t> parse_path_integer(std::string_view text) {
  if (text.empty() || text.size() > 10 || (text.size() > 1 && text[0] == '0')) return std::nullopt;
  uint64_t value = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10 + static_cast<uint64_t>(c - '0');
  }
  if (value > kMaxPathInteger) return std::nullopt;
  return static_cast<uint32_t>(value);
}

bool base64url_text(std::string_view text) {
  for (const char c : text) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                    c == '-' || c == '_';
    if (!ok) return false;
  }
  return true;
}

// Reads codec= and spec= into `route`; anything else is refused, so a typo is not silently
// a second cache entry.
std::optional<Route> read_query(std::string_view query, Route& route) {
  bool seen_codec = false;
  bool seen_spec = false;
  for (const std::string_view pair : split(query, '&')) {
    const std::size_t equals = pair.find('=');
    const std::string_view key = pair.substr(0, equals);
    const std::string_view value =
        equals == std::string_view::npos ? std::string_view{} : pair.substr(equals + 1);
    if (key == "codec" && !seen_codec) {
      seen_codec = true;
      if (value == "zstd") {
        route.codec = Codec::zstd;
      } else if (value == "lz4") {
        route.codec = Codec::lz4;
      } else if (value == "raw") {
        route.codec = Codec::raw;
      } else {
        return refuse(400, "codec = " + quoted(value) + ": must be zstd, lz4 or raw");
      }
    } else if (key == "spec" && !seen_spec) {
      seen_spec = true;
      if (value.size() > kMaxSpecParameterBytes) {
        return refuse(414, "spec is " + std::to_string(value.size()) + " bytes; at most " +
                               std::to_string(kMaxSpecParameterBytes));
      }
      if (value.empty() || !base64url_text(value)) {
        return refuse(400,
                      "spec must be the registration JSON in base64url (A-Z a-z 0-9 - _, "
                      "no padding)");
      }
      route.spec = std::string(value);
    } else if (key == "codec" || key == "spec") {
      return refuse(400, "query parameter " + quoted(key) + " given twice");
    } else {
      return refuse(400, "unknown query parameter " + quoted(key) + " (known: codec, spec)");
    }
  }
  return std::nullopt;
}

std::optional<Route> read_brick_path(const std::vector<std::string_view>& segments, Route& route) {
  static constexpr const char* kNames[] = {"level", "x", "y", "z"};
  uint32_t* const fields[] = {&route.level, &route.x, &route.y, &route.z};
  for (std::size_t i = 0; i < 4; ++i) {
    const std::optional<uint32_t> value = parse_path_integer(segments[5 + i]);
    if (!value) {
      return refuse(400, std::string(kNames[i]) + " = " + quoted(segments[5 + i]) +
                             ": must be a decimal integer in [0, " +
                             std::to_string(kMaxPathInteger) + "] without sign or leading zeros");
    }
    *fields[i] = *value;
  }
  return std::nullopt;
}

// The method against what the resource allows; GET resources also take HEAD (OPTIONS is a
// preflight, answered before).
std::optional<Route> check_method(std::string_view method, std::string_view allowed) {
  if (method == allowed) return std::nullopt;
  if (allowed == "GET, HEAD" && (method == "GET" || method == "HEAD")) return std::nullopt;
  return refuse(405, quoted(method) + " is not allowed here; use " + std::string(allowed),
                std::string(allowed) + ", OPTIONS");
}

// An absolute-form target (RFC 9112 3.2.2, what a client talking to a proxy sends) as the
// origin-form path and query it names; an empty path is "/".
std::string origin_form(std::string_view target) {
  const std::size_t scheme_end = target.find("://");
  if (target.starts_with("/") || scheme_end == std::string_view::npos) return std::string(target);
  for (const char c : target.substr(0, scheme_end)) {
    const bool scheme_char = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                             (c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.';
    if (!scheme_char) return std::string(target);
  }
  const std::string_view rest = target.substr(scheme_end + 3);
  const std::size_t path = rest.find_first_of("/?");
  if (path == std::string_view::npos) return "/";
  return (rest[path] == '?' ? "/" : "") + std::string(rest.substr(path));
}

// A preflight asks whether the real request may be sent; it is answered for any path under
// /v1/textures, so that a malformed one is refused on the real request, where the page can
// read why, rather than as an unreadable CORS failure.
std::optional<Route> preflight(std::string_view method, std::string_view target) {
  if (method != "OPTIONS") return std::nullopt;
  const std::string_view path = target.substr(0, target.find('?'));
  Route route;
  route.kind = RouteKind::preflight;
  if (target == "*") {
    route.allow = "GET, HEAD, POST, OPTIONS";
  } else if (path == "/v1/textures") {
    route.allow = "POST, OPTIONS";
  } else if (path.starts_with("/v1/textures/")) {
    route.allow = "GET, HEAD, OPTIONS";
  } else {
    return std::nullopt;
  }
  return route;
}

Route route_target(std::string_view method, std::string_view raw_target) {
  if (method == "CONNECT") {
    return refuse(501, "CONNECT is not implemented: soltexd is an origin server, not a proxy");
  }
  const std::string origin = origin_form(raw_target);
  const std::string_view target = origin;
  if (auto answered = preflight(method, target)) return *answered;
  const std::size_t question = target.find('?');
  const std::string_view path = target.substr(0, question);
  Route route;
  if (question != std::string_view::npos) {
    if (auto refused = read_query(target.substr(question + 1), route)) return *refused;
  }
  const std::vector<std::string_view> segments = split(path, '/');
  // A path starts with '/', so segments[0] is empty.
  const bool textures = segments.size() >= 3 && segments[0].empty() && segments[1] == "v1" &&
                        segments[2] == "textures";
  const std::string not_found =
      "no resource at " + quoted(path) + "; the routes are " + std::string(kRoutes);
  const std::size_t n = segments.size();
  if (!textures || !(n == 3 || n == 4 || (n == 9 && segments[4] == "bricks"))) {
    return refuse(404, not_found);
  }
  if (segments.size() == 3) {
    route.kind = RouteKind::register_texture;
    if (!route.spec.empty() || route.codec != Codec::zstd) {
      return refuse(400, "POST /v1/textures takes no query parameters");
    }
    if (auto refused = check_method(method, "POST")) return *refused;
    return route;
  }
  const std::optional<uint64_t> id = parse_texture_id(segments[3]);
  if (!id) {
    return refuse(400, "texture id " + quoted(segments[3]) +
                           " is not 16 lower-case hex digits (the id POST /v1/textures returned)");
  }
  route.texture_id = *id;
  if (segments.size() == 4) {
    route.kind = RouteKind::texture;
  } else {
    route.kind = RouteKind::brick;
    if (auto refused = read_brick_path(segments, route)) return *refused;
  }
  if (auto refused = check_method(method, "GET, HEAD")) return *refused;
  return route;
}

}  // namespace

Route route_request(std::string_view method, std::string_view target) {
  Route route = route_target(method, target);
  // Refusals too: a HEAD is answered without content whatever the status.
  route.head = method == "HEAD";
  return route;
}

}  // namespace soltex::server
