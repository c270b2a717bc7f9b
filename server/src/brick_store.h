#pragma once

#include <absl/container/flat_hash_map.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "encoded_brick.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_key.h"

namespace soltex::server {

struct BrickStoreStats {
  uint64_t hits = 0;
  uint64_t misses = 0;
  uint64_t coalesced = 0;  // requests that waited for a brick another request was producing
  uint64_t insertions = 0;
  uint64_t evictions = 0;
  uint64_t bytes = 0;
  uint64_t entries = 0;
};

// The server's cache of encoded bricks under a byte budget: sharded (one mutex per shard),
// least-recently-used eviction per shard, and single-flight: while one caller produces a
// brick, everyone else asking for it waits for that result instead of evaluating it again.
class BrickStore {
 public:
  using Waiter = std::function<void(const EncodedBrickPtr&)>;

  explicit BrickStore(std::size_t byte_budget);

  enum class Claim {
    hit,     // `cached` holds the brick
    owner,   // the caller must produce the brick and publish() it (or abandon() on failure)
    waiter,  // someone else is producing it; `waiter` will be called with the result
  };

  Claim claim(const BrickKey& key, Codec codec, EncodedBrickPtr& cached, Waiter waiter);

  // The cached brick, counted as a hit, or null (not counted: the claim() that follows counts
  // the miss). For answering cache hits where a request arrives, without a worker.
  EncodedBrickPtr find(const BrickKey& key, Codec codec);

  // Stores the brick (evicting others to stay within budget) and hands it to every waiter.
  void publish(const EncodedBrickPtr& brick);
  // The owner failed: waiters are called with nullptr.
  void abandon(const BrickKey& key, Codec codec);

  BrickStoreStats stats() const;
  std::size_t byte_budget() const { return byte_budget_; }

 private:
  struct Entry {
    EncodedBrickPtr brick;
    std::list<const EncodedBrick*>::iterator lru;  // front = most recent
  };
  struct CodecKey {
    BrickKey key;
    Codec codec;
    bool operator==(const CodecKey&) const = default;
  };
  struct CodecKeyHash {
    std::size_t operator()(const CodecKey& k) const noexcept {
      return BrickKeyHash{}(k.key) ^ (static_cast<std::size_t>(k.codec) * 0x9E3779B97F4A7C15ULL);
    }
  };
  // Open addressing (abseil's Swiss table): a cold brick looks its key up several times, and
  // std::unordered_map's node per entry costs each lookup a pointer chase more.
  struct Shard {
    mutable std::mutex mutex;
    absl::flat_hash_map<CodecKey, Entry, CodecKeyHash> entries;
    std::list<const EncodedBrick*> lru;
    absl::flat_hash_map<CodecKey, std::vector<Waiter>, CodecKeyHash> in_flight;
    std::size_t bytes = 0;
  };
  static constexpr std::size_t kShards = 16;

  Shard& shard_for(const CodecKey& key);
  static std::size_t cost(const EncodedBrick& brick);

  const std::size_t byte_budget_;
  const std::size_t shard_budget_;
  std::array<Shard, kShards> shards_;
  std::atomic<uint64_t> hits_{0}, misses_{0}, coalesced_{0}, insertions_{0}, evictions_{0};
};

}  // namespace soltex::server
