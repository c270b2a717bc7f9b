#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "soltex/common/brick_codec.h"

namespace soltex::server {

// What an HTTP request asks for, read from its method and target alone (no body, no server
// state), so the same parse serves the daemon, the tests and the fuzz target.
//
//   POST    /v1/textures                                   register a texture (JSON body)
//   GET     /v1/textures/{id}                              its canonical registration JSON
//   GET     /v1/textures/{id}/bricks/{level}/{x}/{y}/{z}   one encoded brick
//           ?codec=zstd|lz4|raw&spec=BASE64URL             (both optional)
//   OPTIONS any of them                                    CORS preflight
//
// HEAD is accepted wherever GET is.
enum class RouteKind { register_texture, texture, brick, preflight, refused };

struct Route {
  RouteKind kind = RouteKind::refused;
  bool head = false;  // HEAD: answer as GET without the body
  uint64_t texture_id = 0;
  uint32_t level = 0;
  uint32_t x = 0, y = 0, z = 0;
  Codec codec = Codec::zstd;
  std::string spec;  // the base64url registration from ?spec=, empty when absent
  // RouteKind::refused: the HTTP status, a message naming what was wrong, and for 405 the
  // methods the resource allows.
  unsigned status = 0;
  std::string message;
  std::string allow;
};

// The bound on ?spec= (base64url text): a built-in pattern's registration is a few hundred
// bytes, a node graph's about 140 a node. With the path it stays within the 16 KiB the request
// line and headers may take (HttpLimits::max_header_bytes, and nginx's buffers in deploy/).
// POST /v1/textures refuses a registration whose handle would carry more.
inline constexpr std::size_t kMaxSpecParameterBytes = 12288;
// The bound on a brick coordinate or level as written in a path: anything larger cannot be a
// brick of any texture (levels and coordinates are below 2^14 there).
inline constexpr uint32_t kMaxPathInteger = 1u << 30;

Route route_request(std::string_view method, std::string_view target);

}  // namespace soltex::server
