#include "soltex/net/loopback_address.h"

#include <arpa/inet.h>

#include <algorithm>
#include <cctype>
#include <string>

namespace soltex::net {
namespace {

bool starts_with(std::string_view text, std::string_view prefix) {
  return text.substr(0, prefix.size()) == prefix;
}

// The host of HOST, HOST:PORT, [HOST]:PORT or [HOST]; an IPv6 address without brackets
// has several colons and no port.
std::string_view host_of(std::string_view hostport) {
  if (starts_with(hostport, "[")) {
    const std::size_t close = hostport.find(']');
    return close == std::string_view::npos ? hostport : hostport.substr(1, close - 1);
  }
  const std::size_t colon = hostport.find(':');
  if (colon != std::string_view::npos && hostport.find(':', colon + 1) == std::string_view::npos) {
    return hostport.substr(0, colon);
  }
  return hostport;
}

bool is_loopback_host(std::string_view host) {
  std::string name(host);
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (name == "localhost" || name.ends_with(".localhost")) return true;
  in_addr v4{};
  if (inet_pton(AF_INET, name.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  if (inet_pton(AF_INET6, name.c_str(), &v6) == 1) {
    if (IN6_IS_ADDR_LOOPBACK(&v6)) return true;
    return IN6_IS_ADDR_V4MAPPED(&v6) && v6.s6_addr[12] == 127;
  }
  return false;
}

}  // namespace

bool is_loopback_address(std::string_view target) {
  if (starts_with(target, "unix:") || starts_with(target, "unix-abstract:")) return true;
  if (starts_with(target, "dns:")) {
    target.remove_prefix(4);
    if (starts_with(target, "//")) {  // dns://AUTHORITY/HOST:PORT
      const std::size_t slash = target.find('/', 2);
      if (slash == std::string_view::npos) return false;
      target.remove_prefix(slash + 1);
    }
  } else if (starts_with(target, "ipv4:") || starts_with(target, "ipv6:")) {
    target.remove_prefix(5);
    // A list of addresses: loopback only if every one is.
    for (std::size_t begin = 0; begin <= target.size();) {
      const std::size_t comma = std::min(target.find(',', begin), target.size());
      if (!is_loopback_host(host_of(target.substr(begin, comma - begin)))) return false;
      begin = comma + 1;
    }
    return true;
  }
  return !target.empty() && is_loopback_host(host_of(target));
}

}  // namespace soltex::net
