#include "peer_connections.h"

#include <algorithm>

namespace soltex::server {

std::optional<PeerConnections::Slot> PeerConnections::open(const std::string& peer) {
  const std::optional<IpAddress> address = IpAddress::parse(peer);
  const bool unbounded =
      address && std::any_of(unbounded_.begin(), unbounded_.end(),
                             [&](const AddressRange& range) { return range.contains(*address); });
  if (unbounded) return Slot{};
  std::lock_guard lock(mutex_);
  uint32_t& open = open_[peer];
  if (open >= max_per_peer_) return std::nullopt;
  ++open;
  return Slot{shared_from_this(), peer};
}

void PeerConnections::release(const std::string& peer) {
  std::lock_guard lock(mutex_);
  const auto it = open_.find(peer);
  if (it == open_.end()) return;
  if (--it->second == 0) open_.erase(it);
}

}  // namespace soltex::server
