#include "address_range.h"

#include <arpa/inet.h>

#include <charconv>
#include <cstring>
#include <stdexcept>

namespace soltex::server {

std::optional<IpAddress> IpAddress::parse(std::string_view text) {
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']') {
    text = text.substr(1, text.size() - 2);
  }
  if (text.empty() || text.size() > INET6_ADDRSTRLEN) return std::nullopt;
  const std::string copy(text);  // inet_pton needs a terminated string
  IpAddress address;
  in_addr v4{};
  if (inet_pton(AF_INET, copy.c_str(), &v4) == 1) {
    address.bytes[10] = 0xff;
    address.bytes[11] = 0xff;
    std::memcpy(address.bytes.data() + 12, &v4, 4);
    return address;
  }
  in6_addr v6{};
  if (inet_pton(AF_INET6, copy.c_str(), &v6) == 1) {
    std::memcpy(address.bytes.data(), &v6, 16);
    return address;
  }
  return std::nullopt;
}

AddressRange AddressRange::parse(std::string_view text) {
  const auto slash = text.find('/');
  const std::string_view host = text.substr(0, slash);
  const std::optional<IpAddress> address = IpAddress::parse(host);
  if (!address) {
    throw std::invalid_argument("trusted proxy '" + std::string(text) +
                                "' is not an IPv4 or IPv6 address (or ADDRESS/BITS)");
  }
  const bool v4 = host.find(':') == std::string_view::npos;
  AddressRange range;
  range.network_ = *address;
  range.prefix_bits_ = 128;
  if (slash != std::string_view::npos) {
    const std::string_view bits_text = text.substr(slash + 1);
    int bits = -1;
    const auto [end, ec] =
        std::from_chars(bits_text.data(), bits_text.data() + bits_text.size(), bits);
    const int most = v4 ? 32 : 128;
    if (ec != std::errc() || end != bits_text.data() + bits_text.size() || bits < 0 ||
        bits > most) {
      throw std::invalid_argument("trusted proxy '" + std::string(text) +
                                  "': the prefix length must be in [0, " + std::to_string(most) +
                                  "]");
    }
    range.prefix_bits_ = v4 ? 96 + bits : bits;
  }
  return range;
}

bool AddressRange::contains(const IpAddress& address) const {
  int bits = prefix_bits_;
  for (std::size_t i = 0; i < 16 && bits > 0; ++i, bits -= 8) {
    const int take = bits < 8 ? bits : 8;
    const auto mask = static_cast<uint8_t>(0xff00u >> take);
    if ((address.bytes[i] & mask) != (network_.bytes[i] & mask)) return false;
  }
  return true;
}

std::vector<AddressRange> parse_address_ranges(const std::vector<std::string>& texts) {
  std::vector<AddressRange> ranges;
  ranges.reserve(texts.size());
  for (const std::string& text : texts) ranges.push_back(AddressRange::parse(text));
  return ranges;
}

std::string host_of_peer(const std::string& peer) {
  if (!peer.starts_with("ipv4:") && !peer.starts_with("ipv6:")) return peer;
  // gRPC writes IPv6 peers URI-encoded: "ipv6:%5B::1%5D:5000".
  std::string decoded = peer.substr(5);
  for (const auto& [from, to] : {std::pair{"%5B", "["}, std::pair{"%5D", "]"}}) {
    for (auto at = decoded.find(from); at != std::string::npos; at = decoded.find(from)) {
      decoded.replace(at, 3, to);
    }
  }
  std::string_view rest = decoded;
  if (rest.starts_with('[')) {
    const auto close = rest.find(']');
    return std::string(rest.substr(1, close == std::string_view::npos ? rest.npos : close - 1));
  }
  const auto port = rest.rfind(':');
  return std::string(port == std::string_view::npos ? rest : rest.substr(0, port));
}

}  // namespace soltex::server
