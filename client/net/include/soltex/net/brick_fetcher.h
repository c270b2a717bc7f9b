#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/brick_key.h"
#include "soltex/common/cached_brick.h"
#include "soltex/common/texture_spec.h"
#include "soltex/net/brick_source.h"
#include "soltex/net/channel_security.h"
#include "soltex/net/request_bounds.h"

namespace soltex::v1 {
class BrickBatch;
class BrickRequest;
}  // namespace soltex::v1

namespace soltex::net {

// What the fetcher's threads report as it happens, for a start-up timeline: the stream opened,
// a request written (its number of wanted keys), a batch received (its number of bricks,
// corrupt ones included; once its bricks are in the cache, or held out of it while
// hold_arrivals(true)).
enum class FetchEvent { stream_opened, request_written, batch_received };

struct FetcherOptions {
  std::size_t max_in_flight = 256;  // bricks requested and not yet received
  std::chrono::milliseconds initial_backoff{100};
  std::chrono::milliseconds max_backoff{4000};
  std::chrono::milliseconds register_timeout{10000};
  int max_refetches = 3;  // a brick that arrives corrupt is asked for again this many times
  // The codec bricks are asked in (accept_codecs); set_codec() changes it on a live stream.
  Codec codec = Codec::zstd;
  ChannelSecurity security;
  // Called on the fetcher's own threads, outside its lock; keep it short. Null: not reported.
  std::function<void(FetchEvent, std::size_t count)> on_event;
};

// The client's one gRPC stream to soltexd. Render threads hand it each frame's misses; a
// reader thread decodes arriving bricks (checksum verified; a corrupt brick is asked for
// again) and inserts them into the local cache, so the render threads never decode. Every
// stream carries the client's textures in its first message, so it is self-contained and a
// balancer may route it to any replica. When the server goes away the fetcher reconnects with
// exponential backoff and asks again, while the renderer draws on from what the cache holds.
class BrickFetcher final : public BrickSource {
 public:
  BrickFetcher(std::string server_address, BrickCache& cache, FetcherOptions options = {});
  ~BrickFetcher() override;

  BrickFetcher(const BrickFetcher&) = delete;
  BrickFetcher& operator=(const BrickFetcher&) = delete;

  // Registers a texture (idempotent) and returns its id; waits for the server up to
  // FetcherOptions::register_timeout. Throws std::runtime_error with the server's message.
  uint64_t register_texture(const TextureSpec& spec, const Volume& volume, int brick_size,
                            const MipSettings& mip) override;

  // This frame's misses (duplicates allowed). Keys already resident or in flight are skipped;
  // keys in flight that this frame no longer wants are cancelled; the rest are sent in order,
  // up to the in-flight bound.
  void want(std::vector<BrickWant> wants) override;
  // Appends the keys not resident, in flight, failed or waiting, and wakes the writer.
  void want_early(std::vector<BrickWant> wants) override;
  // Held bricks are converted for the cache on the receiving thread as they arrive; release
  // inserts them on the calling thread.
  void hold_arrivals(bool hold) override;

  // Asks for the bricks of later wants in `codec` (bricks in flight keep theirs).
  void set_codec(Codec codec) override;
  std::vector<std::pair<uint64_t, std::string>> take_refused_textures() override;

  // Nothing requested, waiting or in flight.
  bool idle() const override;
  // Blocks until idle() or the timeout passes; returns idle().
  bool wait_idle(std::chrono::milliseconds timeout) override;
  SourceStats stats() const override;

  // Round-trip time of GetServerInfo, and throughput of a short brick burst, for the
  // capability probe. Throws std::runtime_error when the server does not answer within
  // `timeout`.
  std::chrono::microseconds measure_round_trip(
      std::chrono::milliseconds timeout = std::chrono::seconds(5));

 private:
  struct Channel;
  struct Stream;
  struct Warnings;  // per-kind throttles of the warnings a misbehaving server would flood

  void supervise();  // connect, re-register, read until the stream breaks, back off, repeat
  // Up to `backoff` for the channel to connect; false when the fetcher is stopping.
  bool wait_to_reconnect(std::chrono::milliseconds backoff);
  void write_loop();  // sends wants and cancellations as they come
  // What write_loop() has to send, packed into messages within the server's bounds; the
  // wants taken are then in flight. mutex_ held.
  std::vector<v1::BrickRequest> pack_requests();
  // Reads the bounds of the server `stream` is about to open on (ServerInfo.limits); keeps
  // the last known when it does not answer.
  void learn_bounds(Stream& stream);
  void on_batch(v1::BrickBatch& batch);  // its bricks decoded and cached, its errors recorded
  void receive(const std::vector<std::pair<BrickKey, std::string>>& payloads);
  // Appends to waiting_ unless the key waits already; true if it was added.
  bool add_waiting(const BrickWant& want);
  // Puts `key` first in line again (unless it waits already).
  void wait_first(const BrickKey& key);
  // How many may be in flight now: the bounds, or 0 while paused after the server refused
  // wants. mutex_ held.
  std::size_t wants_bound() const;
  // Whether wants may go out now: some wait, and fewer are in flight than wants_bound().
  bool may_send_wants() const;
  // A brick the server refused over a queue bound of the moment: asked for again, at a pace
  // the server keeps up with. mutex_ held.
  void defer(const BrickKey& key);
  // The server refused texture `id` on the stream: its keys leave the queues, later wants of
  // it are ignored, and take_refused_textures() reports it. mutex_ held.
  void refuse_texture(uint64_t id, const std::string& reason);
  bool nothing_pending() const;  // idle(), with mutex_ held

  const std::string address_;
  BrickCache& cache_;
  const FetcherOptions options_;
  std::unique_ptr<Channel> channel_;
  std::unique_ptr<Warnings> warnings_;

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::shared_ptr<Stream> stream_;  // null while disconnected
  // A stream whose call is still starting: gRPC's synchronous start waits for the connection,
  // which a server that accepts but never answers holds for its whole connect timeout (20 s);
  // kept here so that stopping can cancel it.
  std::shared_ptr<Stream> opening_;
  std::unordered_map<uint64_t, std::string> registrations_;  // id -> serialized request
  std::vector<uint64_t> unsent_registrations_;               // registered since the stream opened
  std::vector<BrickWant> waiting_;                           // best first, not yet sent
  std::unordered_set<BrickKey, BrickKeyHash> waiting_keys_;  // waiting_'s keys
  std::unordered_set<BrickKey, BrickKeyHash> in_flight_;
  std::unordered_set<BrickKey, BrickKeyHash> failed_;  // refused by the server: not asked again
  std::unordered_map<BrickKey, int, BrickKeyHash> refetches_;  // corrupt arrivals per key
  std::vector<BrickKey> to_cancel_;
  // The server's bounds on a message and on what one stream may have queued, as its last
  // answer to GetServerInfo gave them: every request is packed to fit them.
  RequestBounds bounds_;
  std::size_t in_flight_bound_;  // options_.max_in_flight, or less when the server queues less
  // After the server refused wants over a queue bound it does not advertise (one shared by
  // several clients of one address): the most in flight, grown by one per brick received
  // back to in_flight_bound_; and, when nothing was left in flight, a pause before more go.
  std::size_t congestion_bound_;
  std::chrono::steady_clock::time_point wants_paused_until_{};
  std::chrono::milliseconds refusal_backoff_{10};
  std::unordered_set<uint64_t> refused_ids_;                        // by the server, on a stream
  std::vector<std::pair<uint64_t, std::string>> refused_textures_;  // not yet taken
  bool resend_ = false;  // a new stream: everything in flight must be asked for again
  Codec codec_;
  bool codec_changed_ = false;  // codec_ goes out with the next request
  bool holding_ = false;        // hold_arrivals(true): arrivals wait in held_
  std::vector<std::pair<BrickKey, CachedBrick>> held_;  // arrived, not yet in the cache
  // held_'s keys, and those being released: each leaves only as it is counted received, so a
  // brick is pending until then (idle(), stats()).
  std::unordered_set<BrickKey, BrickKeyHash> held_keys_;
  SourceStats stats_;
  bool stopping_ = false;
  std::thread supervisor_;
  std::thread writer_;
};

}  // namespace soltex::net
