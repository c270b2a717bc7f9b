#include "brick_store.h"

namespace soltex::server {

BrickStore::BrickStore(std::size_t byte_budget)
    : byte_budget_(byte_budget), shard_budget_(byte_budget / kShards) {}

BrickStore::Shard& BrickStore::shard_for(const CodecKey& key) {
  // The low bits feed the map's buckets; take the shard from the high bits.
  return shards_[(CodecKeyHash{}(key) >> 58) % kShards];
}

std::size_t BrickStore::cost(const EncodedBrick& brick) {
  // The serialized brick plus what the entry costs in the maps and the list, roughly.
  return brick.element().size() + sizeof(EncodedBrick) + 96;
}

BrickStore::Claim BrickStore::claim(const BrickKey& key, Codec codec, EncodedBrickPtr& cached,
                                    Waiter waiter) {
  const CodecKey ck{key, codec};
  Shard& shard = shard_for(ck);
  std::lock_guard lock(shard.mutex);
  if (auto it = shard.entries.find(ck); it != shard.entries.end()) {
    shard.lru.splice(shard.lru.begin(), shard.lru, it->second.lru);
    cached = it->second.brick;
    hits_.fetch_add(1, std::memory_order_relaxed);
    return Claim::hit;
  }
  misses_.fetch_add(1, std::memory_order_relaxed);
  if (auto it = shard.in_flight.find(ck); it != shard.in_flight.end()) {
    it->second.push_back(std::move(waiter));
    coalesced_.fetch_add(1, std::memory_order_relaxed);
    return Claim::waiter;
  }
  shard.in_flight.emplace(ck, std::vector<Waiter>{});
  return Claim::owner;
}

EncodedBrickPtr BrickStore::find(const BrickKey& key, Codec codec) {
  const CodecKey ck{key, codec};
  Shard& shard = shard_for(ck);
  std::lock_guard lock(shard.mutex);
  const auto it = shard.entries.find(ck);
  if (it == shard.entries.end()) return nullptr;
  shard.lru.splice(shard.lru.begin(), shard.lru, it->second.lru);
  hits_.fetch_add(1, std::memory_order_relaxed);
  return it->second.brick;
}

void BrickStore::publish(const EncodedBrickPtr& brick) {
  const CodecKey ck{brick->key, brick->codec};
  Shard& shard = shard_for(ck);
  std::vector<Waiter> waiters;
  {
    std::lock_guard lock(shard.mutex);
    if (auto it = shard.in_flight.find(ck); it != shard.in_flight.end()) {
      waiters = std::move(it->second);
      shard.in_flight.erase(it);
    }
    const std::size_t size = cost(*brick);
    if (size <= shard_budget_ && !shard.entries.contains(ck)) {
      while (shard.bytes + size > shard_budget_ && !shard.lru.empty()) {
        const EncodedBrick* victim = shard.lru.back();
        const CodecKey victim_key{victim->key, victim->codec};
        shard.bytes -= cost(*victim);
        shard.lru.pop_back();
        shard.entries.erase(victim_key);
        evictions_.fetch_add(1, std::memory_order_relaxed);
      }
      shard.lru.push_front(brick.get());
      shard.entries.emplace(ck, Entry{brick, shard.lru.begin()});
      shard.bytes += size;
      insertions_.fetch_add(1, std::memory_order_relaxed);
    }
  }
  // Outside the lock: waiters write to their streams.
  for (const Waiter& waiter : waiters) waiter(brick);
}

void BrickStore::abandon(const BrickKey& key, Codec codec) {
  const CodecKey ck{key, codec};
  Shard& shard = shard_for(ck);
  std::vector<Waiter> waiters;
  {
    std::lock_guard lock(shard.mutex);
    if (auto it = shard.in_flight.find(ck); it != shard.in_flight.end()) {
      waiters = std::move(it->second);
      shard.in_flight.erase(it);
    }
  }
  for (const Waiter& waiter : waiters) waiter(nullptr);
}

BrickStoreStats BrickStore::stats() const {
  BrickStoreStats s;
  s.hits = hits_.load(std::memory_order_relaxed);
  s.misses = misses_.load(std::memory_order_relaxed);
  s.coalesced = coalesced_.load(std::memory_order_relaxed);
  s.insertions = insertions_.load(std::memory_order_relaxed);
  s.evictions = evictions_.load(std::memory_order_relaxed);
  for (const Shard& shard : shards_) {
    std::lock_guard lock(shard.mutex);
    s.bytes += shard.bytes;
    s.entries += shard.entries.size();
  }
  return s;
}

}  // namespace soltex::server
