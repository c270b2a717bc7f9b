#pragma once

#include <string_view>

namespace soltex::net {

// Whether a gRPC target names this machine: a unix socket, localhost, 127.0.0.0/8 or ::1
// (also as ipv4:/ipv6:/dns: targets, with or without a port). Such a link moves bricks at
// memory speed, so a client need not measure it. A port forwarded elsewhere (an SSH tunnel)
// also reads as loopback: such a client names its codec (--codec zstd).
bool is_loopback_address(std::string_view target);

}  // namespace soltex::net
