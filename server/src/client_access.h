#pragma once

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

namespace soltex::server {

struct AccessConfig {
  std::string token;  // empty: no token required
  uint32_t max_streams_per_client = 64;
  uint32_t max_queued_per_client = 65536;
  // Behind a balancer every peer is the balancer: name clients by its x-forwarded-for.
  bool trust_forwarded_for = false;
};

// What one client (one address) holds over all its streams.
struct ClientUsage {
  std::string client;
  uint32_t streams = 0;            // guarded by ClientAccess's mutex
  std::atomic<int64_t> queued{0};  // bricks queued over its streams
};

// Held by a stream for its lifetime: releases the client's stream slot when destroyed.
class StreamLease {
 public:
  StreamLease(class ClientAccess& access, std::shared_ptr<ClientUsage> usage)
      : access_(access), usage_(std::move(usage)) {}
  ~StreamLease() { release(); }
  StreamLease(const StreamLease&) = delete;
  StreamLease& operator=(const StreamLease&) = delete;

  // The stream is over (gRPC is done with it): the slot is free again, even while workers
  // still hold the stream's state. Idempotent.
  void release();

  ClientUsage& usage() const { return *usage_; }

 private:
  ClientAccess& access_;
  std::shared_ptr<ClientUsage> usage_;
  std::atomic<bool> released_{false};
};

// Who may call and how much one client may hold: the bearer token checked on every
// BrickService call (the health service stays open for probes), and the per-client bounds on
// open streams and queued bricks.
class ClientAccess {
 public:
  explicit ClientAccess(AccessConfig config);

  // OK, or UNAUTHENTICATED saying what was missing or wrong.
  grpc::Status authenticate(const grpc::ServerContextBase& context) const;

  // The client's address without its port (or the first x-forwarded-for entry when trusted).
  std::string client_of(const grpc::ServerContextBase& context) const;

  // A stream slot for `client`, or null with `refusal` set to RESOURCE_EXHAUSTED.
  std::unique_ptr<StreamLease> open_stream(const std::string& client, grpc::Status& refusal);

  uint32_t max_queued_per_client() const { return config_.max_queued_per_client; }
  bool token_required() const { return !config_.token.empty(); }

 private:
  friend class StreamLease;
  void close_stream(ClientUsage& usage);

  const AccessConfig config_;
  std::mutex mutex_;
  std::unordered_map<std::string, std::shared_ptr<ClientUsage>> clients_;
};

}  // namespace soltex::server
