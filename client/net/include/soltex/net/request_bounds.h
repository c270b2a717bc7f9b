#pragma once

#include <cstddef>

namespace soltex::net {

// The bounds a server sets on one BrickRequest (its ServerInfo.limits): a message larger than
// max_bytes ends the stream, and one with more than max_wants wants is refused whole.
struct RequestBounds {
  std::size_t max_bytes = 4u << 20;
  std::size_t max_wants = 1024;
};

}  // namespace soltex::net
