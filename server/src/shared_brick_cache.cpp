#include "shared_brick_cache.h"

#include <libmemcached/memcached.h>
#include <libmemcachedutil-1.0/pool.h>
#include <spdlog/spdlog.h>
#include <xxhash.h>

#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <stdexcept>

#include "server_config.h"
#include "soltex/common/texture_id.h"

namespace soltex::server {
namespace {

// A value is the payload behind its own XXH64, so a torn or corrupted value is recognised
// without decoding the brick.
constexpr std::size_t kChecksumBytes = sizeof(uint64_t);

// Borrows one pooled connection for one call.
class PooledConnection {
 public:
  PooledConnection(memcached_pool_st* pool, int timeout_ms) : pool_(pool) {
    timespec wait{timeout_ms / 1000, static_cast<long>(timeout_ms % 1000) * 1000000L};
    memcached_return_t rc;
    connection_ = memcached_pool_fetch(pool_, &wait, &rc);
  }
  ~PooledConnection() {
    if (connection_) memcached_pool_release(pool_, connection_);
  }
  PooledConnection(const PooledConnection&) = delete;
  PooledConnection& operator=(const PooledConnection&) = delete;
  memcached_st* get() const { return connection_; }

 private:
  memcached_pool_st* pool_;
  memcached_st* connection_ = nullptr;
};

int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void set_behavior(memcached_st* m, memcached_behavior_t behavior, uint64_t value) {
  if (memcached_behavior_set(m, behavior, value) != MEMCACHED_SUCCESS) {
    throw std::runtime_error("memcached: cannot set behavior " + std::to_string(behavior));
  }
}

}  // namespace

std::string SharedBrickCache::key_of(const BrickKey& key, Codec codec) {
  return "soltex1:" + texture_id_hex(key.texture) + ":" + std::to_string(key.level) + ":" +
         std::to_string(key.brick.x) + ":" + std::to_string(key.brick.y) + ":" +
         std::to_string(key.brick.z) + ":" + std::to_string(static_cast<int>(codec));
}

SharedBrickCache::SharedBrickCache(const SharedCacheConfig& config)
    : ttl_seconds_(static_cast<uint32_t>(config.ttl_seconds)), timeout_ms_(config.timeout_ms) {
  if (config.servers.empty()) throw std::invalid_argument("memcached: no servers given");
  master_ = memcached_create(nullptr);
  if (!master_) throw std::runtime_error("memcached: out of memory");
  try {
    for (const std::string& server : config.servers) {
      const HostPort address = parse_host_port(server);
      if (address.port == 0) {
        throw std::invalid_argument("memcached server '" + server +
                                    "': port must be in [1, 65535]");
      }
      if (memcached_server_add(master_, address.host.c_str(), address.port) != MEMCACHED_SUCCESS) {
        throw std::invalid_argument("memcached server '" + server + "' is not a usable address");
      }
      auto node = std::make_unique<Node>();
      node->host = address.host;
      node->port = address.port;
      nodes_.push_back(std::move(node));
    }
    const auto timeout = static_cast<uint64_t>(config.timeout_ms);
    set_behavior(master_, MEMCACHED_BEHAVIOR_KETAMA, 1);  // consistent hashing
    set_behavior(master_, MEMCACHED_BEHAVIOR_TCP_NODELAY, 1);
    set_behavior(master_, MEMCACHED_BEHAVIOR_CONNECT_TIMEOUT, timeout);
    set_behavior(master_, MEMCACHED_BEHAVIOR_POLL_TIMEOUT, timeout);
    set_behavior(master_, MEMCACHED_BEHAVIOR_RCV_TIMEOUT, timeout * 1000);
    set_behavior(master_, MEMCACHED_BEHAVIOR_SND_TIMEOUT, timeout * 1000);
    // A node that fails is taken out of the ring and tried again after two seconds, so a dead
    // node costs one failed call per connection, not one per brick.
    set_behavior(master_, MEMCACHED_BEHAVIOR_SERVER_FAILURE_LIMIT, 1);
    set_behavior(master_, MEMCACHED_BEHAVIOR_REMOVE_FAILED_SERVERS, 1);
    set_behavior(master_, MEMCACHED_BEHAVIOR_RETRY_TIMEOUT, 2);
    pool_ =
        memcached_pool_create(master_, 1, static_cast<uint32_t>(std::max(1, config.connections)));
    if (!pool_) throw std::runtime_error("memcached: cannot create the connection pool");
  } catch (...) {
    memcached_free(master_);
    throw;
  }
}

SharedBrickCache::~SharedBrickCache() {
  if (pool_) memcached_pool_destroy(pool_);
  memcached_free(master_);
}

SharedBrickCache::Node* SharedBrickCache::node_of(memcached_st* connection,
                                                  const std::string& name) {
  memcached_return_t rc;
  const memcached_instance_st* server =
      memcached_server_by_key(connection, name.data(), name.size(), &rc);
  if (server == nullptr) return nullptr;
  const char* host = memcached_server_name(server);
  const int port = memcached_server_port(server);
  for (const auto& node : nodes_) {
    if (node->port == port && host != nullptr && node->host == host) return node.get();
  }
  return nullptr;
}

bool SharedBrickCache::resting(const Node* node) {
  if (node == nullptr) return false;
  const int64_t until = node->rest_until_ns.load(std::memory_order_relaxed);
  if (until == 0 || steady_ns() >= until) return false;
  skipped_.fetch_add(1, std::memory_order_relaxed);
  return true;
}

void SharedBrickCache::settle(Node* node, int rc) {
  if (node == nullptr) return;
  const auto code = static_cast<memcached_return_t>(rc);
  // Only a timeout: a node that refuses or drops connections libmemcached ejects itself, and
  // moves its keys to the other nodes, which a rest here would keep from it.
  if (code != MEMCACHED_TIMEOUT) {
    if (code == MEMCACHED_SUCCESS || code == MEMCACHED_NOTFOUND) {
      node->rest_until_ns.store(0, std::memory_order_relaxed);
    }
    return;
  }
  const int64_t until =
      steady_ns() + std::chrono::duration_cast<std::chrono::nanoseconds>(kNodeRest).count();
  if (node->rest_until_ns.exchange(until, std::memory_order_relaxed) == 0) {
    spdlog::warn("memcached {}:{} failed ({}): its keys are misses for {} s", node->host,
                 node->port, memcached_strerror(nullptr, code), kNodeRest.count());
  }
}

std::optional<std::string> SharedBrickCache::fetch(const BrickKey& key, Codec codec) {
  PooledConnection connection(pool_, timeout_ms_);
  if (!connection.get()) {
    errors_.fetch_add(1, std::memory_order_relaxed);
    return std::nullopt;
  }
  const std::string name = key_of(key, codec);
  Node* node = node_of(connection.get(), name);
  if (resting(node)) return std::nullopt;
  std::size_t length = 0;
  uint32_t flags = 0;
  memcached_return_t rc;
  std::unique_ptr<char, decltype(&std::free)> value(
      memcached_get(connection.get(), name.data(), name.size(), &length, &flags, &rc), &std::free);
  settle(node, rc);
  if (rc == MEMCACHED_NOTFOUND) {
    misses_.fetch_add(1, std::memory_order_relaxed);
    return std::nullopt;
  }
  if (rc != MEMCACHED_SUCCESS || !value) {
    errors_.fetch_add(1, std::memory_order_relaxed);
    spdlog::debug("memcached get {}: {}", name, memcached_strerror(connection.get(), rc));
    return std::nullopt;
  }
  uint64_t stored_checksum = 0;
  if (length < kChecksumBytes) {
    corrupt_.fetch_add(1, std::memory_order_relaxed);
    return std::nullopt;
  }
  std::memcpy(&stored_checksum, value.get(), kChecksumBytes);
  std::string payload(value.get() + kChecksumBytes, length - kChecksumBytes);
  if (XXH64(payload.data(), payload.size(), 0) != stored_checksum) {
    corrupt_.fetch_add(1, std::memory_order_relaxed);
    spdlog::warn("memcached value for {} fails its checksum; evaluating instead", name);
    return std::nullopt;
  }
  hits_.fetch_add(1, std::memory_order_relaxed);
  return payload;
}

void SharedBrickCache::store(const BrickKey& key, Codec codec, std::string_view payload) {
  PooledConnection connection(pool_, timeout_ms_);
  if (!connection.get()) {
    store_errors_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  const std::string name = key_of(key, codec);
  Node* node = node_of(connection.get(), name);
  if (resting(node)) return;
  std::string value(kChecksumBytes, '\0');
  const uint64_t checksum = XXH64(payload.data(), payload.size(), 0);
  std::memcpy(value.data(), &checksum, kChecksumBytes);
  value.append(payload);
  const memcached_return_t rc = memcached_set(connection.get(), name.data(), name.size(),
                                              value.data(), value.size(), ttl_seconds_, 0);
  settle(node, rc);
  if (rc == MEMCACHED_SUCCESS) {
    stores_.fetch_add(1, std::memory_order_relaxed);
  } else {
    store_errors_.fetch_add(1, std::memory_order_relaxed);
    spdlog::debug("memcached set {}: {}", name, memcached_strerror(connection.get(), rc));
  }
}

SharedCacheStats SharedBrickCache::stats() const {
  return {hits_.load(std::memory_order_relaxed),   misses_.load(std::memory_order_relaxed),
          errors_.load(std::memory_order_relaxed), corrupt_.load(std::memory_order_relaxed),
          stores_.load(std::memory_order_relaxed), store_errors_.load(std::memory_order_relaxed),
          skipped_.load(std::memory_order_relaxed)};
}

}  // namespace soltex::server
