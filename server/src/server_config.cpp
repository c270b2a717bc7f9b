#include "server_config.h"

#include <charconv>
#include <stdexcept>
#include <string>

namespace soltex::server {

HostPort parse_host_port(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) {
    throw std::invalid_argument("address '" + text + "' must be HOST:PORT");
  }
  std::string host = text.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  }
  unsigned port = 0;
  const char* begin = text.data() + colon + 1;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(begin, end, port);
  if (ec != std::errc() || ptr != end || port > 65535) {
    throw std::invalid_argument("address '" + text + "': port must be in [0, 65535]");
  }
  return {host, static_cast<uint16_t>(port)};
}

std::string host_port_text(const std::string& host, int port) {
  return (host.find(':') != std::string::npos ? "[" + host + "]" : host) + ":" +
         std::to_string(port);
}

bool is_unix_socket_address(const std::string& address) {
  return address.starts_with("unix:") || address.starts_with("unix-abstract:");
}

}  // namespace soltex::server
