#pragma once

#include <absl/container/flat_hash_map.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

#include <atomic>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>

#include "brick_batch_reader.h"
#include "load_recorder.h"
#include "request_budget.h"
#include "request_mix.h"
#include "soltex/net/channel_security.h"
#include "soltex/v1/brick_service.grpc.pb.h"

namespace soltex::load {

// StreamBricks with the answers as raw bytes, read by BrickBatchReader.
using BrickStreamStub = grpc::TemplatedGenericStub<v1::BrickRequest, grpc::ByteBuffer>;
inline constexpr const char* kStreamBricksMethod = "/soltex.v1.BrickService/StreamBricks";

// One StreamBricks call under load (gRPC callback API). Requests are issued into a backlog
// and sent as soon as the single write in flight allows, many keys per message; answers are
// matched to the request they answer by key. The stream never waits for the same key twice at
// once (the server would merge the two): such a request is parked, by key, until the first is
// answered, its latency still counting from its intended time. Parking by key keeps each send
// proportional to what it sends, however many requests wait.
//
// Closed loop: every answer issues the next request at once, keeping `in_flight` outstanding.
// Open loop: the scheduler calls issue() at the intended times.
class LoadStream final : public grpc::ClientBidiReactor<v1::BrickRequest, grpc::ByteBuffer> {
 public:
  struct Settings {
    int in_flight = 0;  // closed loop; 0: open loop
    uint32_t max_keys_per_request = 1024;
    std::size_t max_message_bytes = 4u << 20;  // the server's; a larger message ends the stream
    std::size_t max_backlog = 1'000'000;
    v1::Codec codec = v1::CODEC_ZSTD;
    bool verify = false;
    const net::ChannelSecurity* security = nullptr;  // the bearer token, if any
    v1::RegisterTextureRequest texture;              // sent in the stream's first message
  };

  LoadStream(BrickStreamStub& stub, const Settings& settings, std::unique_ptr<RequestMix> mix,
             LoadRecorder& recorder, RequestBudget& budget, std::function<void()> on_done);

  // Opens the call; in closed loop issues the first `in_flight` requests.
  void start();
  // Open loop: one request meant to be sent at `intended`. False when the stream no longer
  // takes requests (closing, ended, or the count is spent).
  bool issue(Clock::time_point intended);
  // No new requests: send what was issued, then half-close; the server ends the call once it
  // has answered everything.
  void close();
  // Drain timeout: end the call now; what is still owed is counted as unanswered, and the
  // stream as let go, not as one that failed.
  void cancel() {
    cancelled_here_.store(true);
    context_.TryCancel();
  }
  bool done() const;

  void OnReadDone(bool ok) override;
  void OnWriteDone(bool ok) override;
  void OnDone(const grpc::Status& status) override;

 private:
  struct Pending {
    PlannedWant want;
    Clock::time_point intended;
  };
  struct Starts {
    bool write = false;
    bool writes_done = false;
    bool any() const { return write || writes_done; }
  };

  // mutex_ held for all *_locked.
  bool issue_locked(Clock::time_point intended);
  void park_locked(Pending pending);
  void unpark_locked(const BrickKey& key);  // `key` was answered: its first parked request goes
  Starts next_starts_locked();
  // Starts the operations outside the lock (gRPC may run reactions on this thread), then
  // releases the hold that keeps the call open while operations may still be started from
  // outside a reaction.
  void perform(Starts starts);
  void answer_locked(const BrickKey& key, Clock::time_point now, std::size_t bytes, int error_code);
  void check_bricks();  // the bricks of batch_, payloads kept

  const Settings settings_;
  std::unique_ptr<RequestMix> mix_;
  LoadRecorder& recorder_;
  RequestBudget& budget_;
  std::function<void()> on_done_;
  BrickStreamStub& stub_;
  grpc::ClientContext context_;

  mutable std::mutex mutex_;
  std::deque<Pending> backlog_;  // ready to send, oldest first
  // Open addressing (abseil's Swiss table): a closed loop looks keys up several times per
  // request, which std::unordered_map (a prime modulo and a node per entry) made 8 % of
  // soltex-load's CPU under a hot load.
  absl::flat_hash_map<BrickKey, std::deque<Pending>, BrickKeyHash> parked_;
  std::size_t parked_count_ = 0;
  absl::flat_hash_map<BrickKey, Clock::time_point, BrickKeyHash> outstanding_;  // -> intended
  v1::BrickRequest write_;  // owned by the write in flight
  grpc::ByteBuffer read_;   // owned by the read in flight
  BrickBatchReader batch_;  // the last message read
  bool texture_sent_ = false;
  bool writing_ = false;
  bool closing_ = false;
  bool half_closed_ = false;
  bool reads_ended_ = false;
  bool hold_released_ = false;
  bool done_ = false;
  std::atomic<bool> cancelled_here_{false};  // cancel() ran: a CANCELLED end is ours
  int starting_ = 0;                         // threads between deciding on a start and making it
};

}  // namespace soltex::load
