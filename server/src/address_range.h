#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace soltex::server {

// An IPv4 or IPv6 address; IPv4 is kept as its IPv4-mapped IPv6 form (::ffff:a.b.c.d), so
// "10.0.0.1" and "::ffff:10.0.0.1" are the same address, as a dual-stack socket reports it.
struct IpAddress {
  std::array<uint8_t, 16> bytes{};

  // "10.0.0.1", "::1", "[::1]", "::ffff:10.0.0.1"; nullopt for anything else.
  static std::optional<IpAddress> parse(std::string_view text);
  bool operator==(const IpAddress&) const = default;
};

// An address or a CIDR block: "10.0.0.7", "10.0.0.0/8", "fd00::/8", "::1".
class AddressRange {
 public:
  // Throws std::invalid_argument naming the text and what is wrong with it.
  static AddressRange parse(std::string_view text);

  bool contains(const IpAddress& address) const;

 private:
  IpAddress network_;
  int prefix_bits_ = 128;  // of the 128-bit (mapped) form
};

// Every entry parsed; throws std::invalid_argument naming the first bad one.
std::vector<AddressRange> parse_address_ranges(const std::vector<std::string>& texts);

// The host part of a gRPC peer string: "ipv4:127.0.0.1:5000" -> "127.0.0.1",
// "ipv6:[::1]:5000" -> "::1"; anything else (unix sockets) unchanged.
std::string host_of_peer(const std::string& peer);

}  // namespace soltex::server
