#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "address_range.h"

namespace soltex::server {

// Open connections per peer address, bounded, so that one peer holding connections open (a
// slow reader, or a request sent a byte a second and sent again when closed) cannot take every
// slot of the server's connection bound. Balancers named as trusted proxies carry many clients'
// connections and are not bounded here. Thread-safe.
class PeerConnections : public std::enable_shared_from_this<PeerConnections> {
 public:
  // A connection's slot, given back when destroyed.
  class Slot {
   public:
    Slot() = default;
    Slot(std::shared_ptr<PeerConnections> owner, std::string peer)
        : owner_(std::move(owner)), peer_(std::move(peer)) {}
    Slot(Slot&&) = default;
    Slot& operator=(Slot&&) = default;
    ~Slot() {
      if (owner_) owner_->release(peer_);
    }

   private:
    std::shared_ptr<PeerConnections> owner_;
    std::string peer_;
  };

  PeerConnections(uint32_t max_per_peer, std::vector<AddressRange> unbounded)
      : max_per_peer_(max_per_peer), unbounded_(std::move(unbounded)) {}

  // A slot for a connection from `peer` (its address as text), or nullopt when the peer holds
  // max_per_peer already.
  std::optional<Slot> open(const std::string& peer);
  uint32_t max_per_peer() const { return max_per_peer_; }

 private:
  void release(const std::string& peer);

  const uint32_t max_per_peer_;
  const std::vector<AddressRange> unbounded_;
  std::mutex mutex_;
  std::unordered_map<std::string, uint32_t> open_;
};

}  // namespace soltex::server
