#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_key.h"

struct memcached_st;
struct memcached_pool_st;

namespace soltex::server {

struct SharedCacheConfig {
  std::vector<std::string> servers;  // HOST:PORT each; empty: no shared cache
  int timeout_ms = 50;               // connect and I/O; a slow node counts as a miss
  int ttl_seconds = 0;               // 0: until memcached evicts it
  int connections = 16;              // pooled connections (one per busy worker is enough)
};

struct SharedCacheStats {
  uint64_t hits = 0;
  uint64_t misses = 0;
  uint64_t errors = 0;   // node unreachable, timed out or refused: treated as a miss
  uint64_t corrupt = 0;  // value failed its checksum: treated as a miss
  uint64_t stores = 0;
  uint64_t store_errors = 0;
  uint64_t skipped = 0;  // lookups and write-backs not tried: their node rests after a timeout
};

// The second-level brick cache that replicas share: encoded bricks in memcached, spread over
// the nodes by consistent hashing (ketama), so adding or losing a node moves only its share of
// the keys. It never fails a request: an unreachable, slow or dead node is a miss (and is
// ejected for a few seconds), and a value that does not match its checksum is a miss. A node
// that times out rests for kNodeRest: the keys it holds are misses meanwhile, without a call
// (libmemcached ejects a node that refuses connections, not one that accepts them and never
// answers, which would cost every brick a timeout on the lookup and another on the write-back).
// Thread-safe; connections come from a pool.
class SharedBrickCache {
 public:
  // Throws std::invalid_argument naming a server address that does not parse.
  explicit SharedBrickCache(const SharedCacheConfig& config);
  ~SharedBrickCache();
  SharedBrickCache(const SharedBrickCache&) = delete;
  SharedBrickCache& operator=(const SharedBrickCache&) = delete;

  std::optional<std::string> fetch(const BrickKey& key, Codec codec);
  void store(const BrickKey& key, Codec codec, std::string_view payload);

  SharedCacheStats stats() const;

  static constexpr std::chrono::seconds kNodeRest{2};

  // The memcached key of a brick: versioned, so a format change never reads old values.
  static std::string key_of(const BrickKey& key, Codec codec);

 private:
  // A node of the ring, and until when it rests (steady clock, ns; 0: not resting).
  struct Node {
    std::string host;
    int port = 0;
    std::atomic<int64_t> rest_until_ns{0};
  };
  // The node `name` hashes to on `connection`, or null when libmemcached names none.
  Node* node_of(memcached_st* connection, const std::string& name);
  // Whether a call to `node` is skipped now (counted in `skipped_`).
  bool resting(const Node* node);
  // After a call to `node` returned `rc`: a timeout makes it rest, an answer ends its rest.
  void settle(Node* node, int rc);

  std::vector<std::unique_ptr<Node>> nodes_;
  memcached_st* master_ = nullptr;
  memcached_pool_st* pool_ = nullptr;
  const uint32_t ttl_seconds_;
  const int timeout_ms_;
  std::atomic<uint64_t> hits_{0}, misses_{0}, errors_{0}, corrupt_{0}, stores_{0}, store_errors_{0},
      skipped_{0};
};

}  // namespace soltex::server
