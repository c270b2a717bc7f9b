#pragma once

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "access_tokens.h"
#include "address_range.h"

namespace soltex::server {

struct AccessConfig {
  std::vector<AccessToken> tokens;  // empty: no token required
  uint32_t max_streams_per_client = 64;
  uint32_t max_queued_per_client = 65536;
  // Peers whose x-forwarded-for header names the client (the balancers in front of soltexd).
  std::vector<AddressRange> trusted_proxies;
};

// What one client (one identity) holds over all its streams.
struct ClientUsage {
  std::string client;
  uint32_t streams = 0;            // guarded by ClientAccess's mutex
  std::atomic<int64_t> queued{0};  // bricks queued over its streams
};

// Who a caller is by address: `peer_host` (its address without the port) unless it is a
// trusted proxy; then the last x-forwarded-for entry (`forwarded`, in header order) that no
// trusted proxy wrote, or the first when every one is trusted. An entry that is not an address
// ends the search at the peer: no proxy of ours wrote it.
std::string client_address(const std::string& peer_host,
                           const std::vector<std::string_view>& forwarded,
                           const std::vector<AddressRange>& trusted_proxies);

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

// Who may call and how much one client may hold: the bearer tokens checked on every
// BrickService call (the health service stays open for probes), who the caller is, and the
// per-client bounds on open streams and queued bricks.
//
// A client is an identity: "token:NAME" for a caller with a named token, else its address:
// the x-forwarded-for entry a trusted proxy wrote when the peer is one, else the peer's.
class ClientAccess {
 public:
  explicit ClientAccess(AccessConfig config);

  // OK with `client` set to the caller's identity, or UNAUTHENTICATED saying what was missing
  // or wrong (`client` is then its address, for the log).
  grpc::Status identify(const grpc::ServerContextBase& context, std::string& client) const;

  // The same check for a caller whose address is already known (an HTTP request):
  // `authorization` is the header's value, nullptr when absent. `client` comes in as the
  // address and leaves as the identity.
  grpc::Status check_token(const std::string_view* authorization, std::string& client) const;

  // An HTTP caller's address: the peer, or what x-forwarded-for names when the peer is a
  // trusted proxy (`forwarded`: the header's values, in order).
  std::string address_of(const std::string& peer_host,
                         const std::vector<std::string_view>& forwarded) const;

  // The caller's address without its port: the client x-forwarded-for names when the peer is
  // a trusted proxy, else the peer.
  std::string address_of(const grpc::ServerContextBase& context) const;

  // A stream slot for `client`, or null with `refusal` set to RESOURCE_EXHAUSTED.
  std::unique_ptr<StreamLease> open_stream(const std::string& client, grpc::Status& refusal);

  // SIGHUP: later calls are checked against these tokens; open streams are not touched.
  // Tokens may not be turned on or off this way (empty keeps requiring none, and is refused
  // when tokens are required).
  void replace_tokens(std::vector<AccessToken> tokens);

  uint32_t max_queued_per_client() const { return config_.max_queued_per_client; }
  bool token_required() const { return token_required_; }

 private:
  friend class StreamLease;
  void close_stream(ClientUsage& usage);
  std::shared_ptr<const std::vector<AccessToken>> tokens() const;

  const AccessConfig config_;
  const bool token_required_;
  mutable std::mutex tokens_mutex_;
  std::shared_ptr<const std::vector<AccessToken>> tokens_;
  std::mutex mutex_;
  std::unordered_map<std::string, std::shared_ptr<ClientUsage>> clients_;
};

}  // namespace soltex::server
