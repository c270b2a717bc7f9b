#pragma once

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "brick_producer.h"
#include "brick_scheduler.h"
#include "client_access.h"
#include "fault_injection.h"
#include "refusal_log.h"
#include "server_metrics.h"
#include "soltex/v1/brick_service.grpc.pb.h"
#include "texture_registry.h"
#include "work_queue.h"

namespace soltex::server {

struct StreamLimits {
  uint32_t max_keys_per_request = 1024;
  uint32_t max_queued_per_stream = 4096;
  uint32_t max_batch_bricks = 32;
  uint32_t max_batch_bytes = 1 << 20;
  uint32_t max_queued_per_client = 65536;  // over all of one client's streams
  // A message is held back while it has fewer bricks than this, more of the stream's bricks
  // are queued or being made, and its oldest brick has waited less than coalesce_wait (a timer
  // sends it then): on a fast link a write completes before the next brick is made, and without
  // this most messages would carry one or two bricks, each costing both ends a wake-up.
  uint32_t coalesce_bricks = 32;
  std::chrono::microseconds coalesce_wait{2000};
  // While more streams wait for a worker than there are workers, a stream's turn makes up to
  // this many of its bricks, one after the other, instead of one: its turn comes round seldom,
  // and bricks made one a turn would each travel alone, a message costing both ends about as
  // much CPU as a quarter of a cold brick. Every stream still gets the same share. A run's
  // bricks go in one message however long the run takes (the coalesce wait does not cut it),
  // so this also bounds how long a run's first brick waits for its last.
  uint32_t run_bricks = 16;
  // A run also ends once it has taken this long, its other bricks going back to the queue: a
  // run is for bricks cheap enough to share a message (16 cold marble bricks: about 2.5 ms);
  // an expensive texture's run would hold a worker for its whole length (16 supersampled
  // bricks: 16 s) while every other stream waited for one.
  std::chrono::microseconds run_time{5000};
  // Made bricks a stream may hold unsent (its outbox and the write in flight) before its
  // queued bricks wait for the client to read: the count bounds (max_queued_*) hold keys, but
  // a client that stops reading would otherwise make the server keep every brick made for it
  // (65,536 raw bricks of one client: 1.5 GiB).
  std::size_t max_unsent_bytes = std::size_t{2} << 20;
};

// Everything one StreamBricks call needs, shared between the gRPC reactor (gRPC threads) and
// the workers producing its bricks (our pool). The reactor object itself belongs to gRPC and
// is deleted in OnDone; this state outlives it for as long as a worker holds it.
//
// One write in flight at a time; the next request is read only while what the stream owes
// (queued, in production, not yet written) leaves room for a whole request (backpressure: a
// client that asks faster than it reads is slowed by HTTP/2 flow control, not by an unbounded
// queue).
class BrickStream final : public WorkSource, public std::enable_shared_from_this<BrickStream> {
 public:
  struct Context {
    TextureRegistry& registry;
    BrickScheduler& scheduler;
    BrickProducer& producer;
    ServerMetrics& metrics;
    FaultInjection& faults;
    RefusalLog& refusals;
    StreamLimits limits;
  };

  BrickStream(Context context, uint64_t id, std::string peer, std::unique_ptr<StreamLease> lease);
  ~BrickStream() override;

  // The call's messages travel as raw bytes: requests are parsed here, and a message of
  // bricks is written as the bricks' serialized entries side by side (EncodedBrick).
  using ServerReactor = grpc::ServerBidiReactor<grpc::ByteBuffer, grpc::ByteBuffer>;

  // Creates the gRPC reactor bound to this stream and starts reading.
  ServerReactor* start();

  // Server shutdown, first step: read no more requests, send every brick already asked for,
  // then finish: OK if the client had half-closed, else UNAVAILABLE (ask another server).
  void drain();
  // Server shutdown, at the end of the grace: drop queued work and finish with UNAVAILABLE once
  // the current write is done.
  void shut_down();

  std::function<void()> take() override;
  // A request read and not yet handled; or queued bricks, and room to hold what they become
  // (max_unsent_bytes).
  bool has_work() const override {
    return request_queued_.load(std::memory_order_relaxed) || (queue_.size() > 0 && !unsent_full());
  }

 private:
  class Reactor;
  struct Outgoing {
    EncodedBrickPtr brick;                // or
    std::optional<v1::BrickError> error;  // or
    std::optional<v1::RequestError> request_error;
    std::chrono::steady_clock::time_point enqueued;  // when its request was queued
    std::chrono::steady_clock::time_point ready;     // when it entered the outbox
  };

  // Reactor callbacks (gRPC threads).
  void on_read_done(bool ok);
  void on_write_done(bool ok);
  void on_cancel();
  void on_done();

  // Worker callbacks.
  void handle_request();  // parses the request read last and queues what it asks for
  // in_run: the item is one of a run's (take()), counted in run_unmade_ until delivered.
  void deliver(const WorkItem& item, const EncodedBrickPtr& brick, bool in_run);
  // Whether the stream sends no more bricks (cancelled, shutting down, finished); if so, lets go
  // of one taken item without making it, counted as cancelled.
  bool let_go_if_gone(bool in_run);
  void begin_run(std::size_t bricks);         // a worker starts making a run of this many bricks
  void give_back(std::span<WorkItem> items);  // a run's unmade rest, back in the queue
  // A made brick into the outbox, counted in unsent_bytes_. mutex_ held.
  void add_to_outbox(EncodedBrickPtr brick, std::chrono::steady_clock::time_point enqueued,
                     std::chrono::steady_clock::time_point ready);

  // All below: mutex_ held.
  std::size_t accept_request();  // returns how many keys were queued
  // The key to queue or answer, or none: refused (an error added), already in this request, or
  // merged with the same key still queued (at a queue bound, where a push could not be).
  std::optional<BrickKey> admitted_key(const v1::BrickKey& k, int32_t priority,
                                       const BrickLayout& layout);
  bool first_in_request(const BrickKey& key);  // false: the request named it before
  void register_textures();
  TexturePtr use_texture(uint64_t id);  // pinned for the stream's life; null: not registered
  void count_queued(int64_t delta);     // this stream's queue grew or shrank by delta
  void drop_queue();                    // empties the queue, counted
  void add_error(const v1::BrickKey& key, grpc::StatusCode code, std::string message);
  // A want refused over a queue bound: RESOURCE_EXHAUSTED for the client, and a line in the
  // refusal log (at most one a second per client).
  void refuse_over_queue_bound(const v1::BrickKey& k, const std::string& why);
  // texture_id: the request's texture the error refused, 0 for the whole request.
  void add_request_error(grpc::StatusCode code, std::string message, uint64_t texture_id = 0);
  bool answer_from_cache(const BrickKey& key, std::chrono::steady_clock::time_point now);
  void write_outbox();         // starts the write of the next message from the outbox
  void pump();                 // start the next read, write or finish, whichever is due
  std::size_t owed() const;    // bricks queued, in production or waiting to be written
  bool held_for_run() const;   // whether the outbox waits for the rest of a run being made
  bool hold_back() const;      // whether the outbox should wait for more bricks (coalescing)
  void pump_when_wait_ends();  // arms coalesce_timer_ for the outbox's oldest brick

  Context context_;
  const uint64_t id_;
  const std::string peer_;
  const std::chrono::steady_clock::time_point opened_;
  const std::unique_ptr<StreamLease> lease_;

  // Recursive: gRPC may run a reaction inline from an operation we start under the lock.
  std::recursive_mutex mutex_;
  Reactor* reactor_ = nullptr;      // null once gRPC has called OnDone
  grpc::ByteBuffer request_bytes_;  // owned by the read in flight
  // The request read last, until a worker's turn handles it; the next is read only then.
  grpc::ByteBuffer unhandled_request_;
  bool request_unhandled_ = false;
  std::atomic<bool> request_queued_{false};  // read, and not yet taken by a worker (take())
  v1::BrickRequest request_;                 // the last request read, parsed
  grpc::ByteBuffer batch_;                   // owned by the write in flight
  std::vector<grpc::Slice> batch_slices_;
  v1::BrickBatch batch_errors_;  // the errors of the message being assembled
  std::vector<std::chrono::steady_clock::time_point> batch_enqueued_;
  std::vector<std::chrono::steady_clock::time_point> batch_ready_;
  std::chrono::steady_clock::time_point write_started_;
  std::deque<Outgoing> outbox_;
  Codec codec_ = Codec::zstd;
  bool reading_ = false;
  bool reads_done_ = false;
  bool writing_ = false;
  bool finished_ = false;
  bool draining_ = false;             // drain(): no more reads
  bool request_after_drain_ = false;  // a message arrived after drain(), dropped unread
  bool shutting_down_ = false;        // shut_down(): no more bricks
  bool cancelled_ = false;
  // Keys of the request being accepted (a key wanted twice in one message is sent once): the
  // first few in a vector, all of them in the set past that. Both kept to reuse their memory.
  std::vector<BrickKey> seen_keys_;
  std::unordered_set<BrickKey, BrickKeyHash> seen_set_;

  // Every texture the stream registered or asked for, kept from eviction until it ends.
  std::unordered_map<uint64_t, TexturePin> pins_;

  WorkQueue queue_;  // queued bricks, and those taken by a worker and not yet delivered
  // Sends a held-back message when its wait ends, should no delivery come first to do it.
  boost::asio::steady_timer coalesce_timer_;
  bool coalesce_timer_armed_ = false;
  // Bricks of runs being made on workers and not yet delivered (or let go).
  std::size_t run_unmade_ = 0;

  // Totals for the close log line.
  uint64_t batches_sent_ = 0;
  uint64_t bricks_sent_ = 0;
  uint64_t bytes_sent_ = 0;
  // Bytes of the bricks in outbox_ and in the write in flight; written under mutex_, read
  // without it by the scheduler (has_work(), take()): a brick more or less does not matter.
  std::atomic<std::size_t> unsent_bytes_{0};
  std::size_t writing_bytes_ = 0;       // of the write in flight
  std::atomic<bool> throttled_{false};  // take() held work back for unsent_bytes_
  bool unsent_full() const {
    return unsent_bytes_.load(std::memory_order_relaxed) >= context_.limits.max_unsent_bytes;
  }
  uint64_t errors_sent_ = 0;
};

}  // namespace soltex::server
