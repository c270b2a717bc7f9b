#include "brick_stream.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "soltex/common/quoted_text.h"
#include "soltex/common/texture_id.h"
#include "soltex/spec_proto/brick_proto.h"
#include "texture_registration.h"

namespace soltex::server {

class BrickStream::Reactor final : public BrickStream::ServerReactor {
 public:
  explicit Reactor(std::shared_ptr<BrickStream> stream) : stream_(std::move(stream)) {}

  void OnReadDone(bool ok) override { stream_->on_read_done(ok); }
  void OnWriteDone(bool ok) override { stream_->on_write_done(ok); }
  void OnCancel() override { stream_->on_cancel(); }
  void OnDone() override {
    stream_->on_done();
    delete this;
  }

 private:
  std::shared_ptr<BrickStream> stream_;
};

namespace {

// The id a refused texture would have had, so that the client knows which of its textures it
// was; 0 where its spec gives none.
uint64_t id_of_refused(const v1::RegisterTextureRequest& texture) {
  try {
    return registration_id(texture);
  } catch (const RegistrationError&) {
    return 0;
  }
}

// A brick's entry as sent, with the last payload byte flipped when fault injection says this
// send is due for it; otherwise the cached entry itself.
grpc::Slice element_to_send(const EncodedBrick& brick, FaultInjection& faults) {
  if (!faults.corrupts()) return brick.element();
  std::string payload(brick.payload());
  if (!faults.corrupt_if_due(payload)) return brick.element();
  return EncodedBrick(brick.key, brick.codec, payload, brick.checksum).element();
}

std::string describe(const v1::BrickKey& key) {
  return "brick (" + std::to_string(key.x()) + ", " + std::to_string(key.y()) + ", " +
         std::to_string(key.z()) + ") level " + std::to_string(key.level()) + " of texture " +
         texture_id_hex(key.texture_id());
}

}  // namespace

BrickStream::BrickStream(Context context, uint64_t id, std::string peer,
                         std::unique_ptr<StreamLease> lease)
    : context_(context),
      id_(id),
      peer_(std::move(peer)),
      opened_(std::chrono::steady_clock::now()),
      lease_(std::move(lease)),
      coalesce_timer_(context_.scheduler.timer_executor()) {
  context_.metrics.streams_opened.fetch_add(1, std::memory_order_relaxed);
  context_.metrics.streams_open.fetch_add(1, std::memory_order_relaxed);
  // Turns are shared between clients: this client's streams draw on one account.
  share_with(context_.scheduler.share_of(lease_->usage().client));
}

BrickStream::~BrickStream() {
  context_.metrics.streams_open.fetch_sub(1, std::memory_order_relaxed);
  drop_queue();
  // Bricks made for a stream that was cancelled before it could write them.
  const auto unsent = std::count_if(outbox_.begin(), outbox_.end(),
                                    [](const Outgoing& o) { return o.brick != nullptr; });
  context_.metrics.bricks_cancelled.fetch_add(static_cast<uint64_t>(unsent),
                                              std::memory_order_relaxed);
}

void BrickStream::drop_queue() {
  // Requested and now never sent: the stream was cancelled, shut down or is gone.
  const std::size_t dropped = queue_.clear();
  context_.metrics.bricks_cancelled.fetch_add(dropped, std::memory_order_relaxed);
  count_queued(-static_cast<int64_t>(dropped));
}

void BrickStream::count_queued(int64_t delta) {
  context_.metrics.queue_depth.fetch_add(delta, std::memory_order_relaxed);
  lease_->usage().queued.fetch_add(delta, std::memory_order_relaxed);
}

BrickStream::ServerReactor* BrickStream::start() {
  std::lock_guard lock(mutex_);
  reactor_ = new Reactor(shared_from_this());
  // One info line per stream, when it closes with its totals; many short streams would
  // otherwise double the log.
  spdlog::debug("stream {} opened by {}", id_, peer_);
  pump();
  return reactor_;
}

void BrickStream::on_read_done(bool ok) {
  // Handled here, on gRPC's thread, while the budget for that lasts; otherwise on a worker's
  // turn, charged to this client's share. Either way the next message is read only after.
  const bool here = ok && context_.scheduler.direct_requests().has_credit();
  {
    std::lock_guard lock(mutex_);
    reading_ = false;
    if (!ok) {
      reads_done_ = true;  // the client half-closed (or the call is over)
    } else if (draining_) {
      // A read started before the shutdown and completed after it: the message came after
      // the shutdown began, so it is not read (its bricks are not owed), and no read follows.
      request_after_drain_ = true;
      pump();
      return;
    } else {
      context_.metrics.stream_messages.fetch_add(1, std::memory_order_relaxed);
      unhandled_request_.Swap(&request_bytes_);
      request_unhandled_ = true;
      if (!here) {
        request_queued_.store(true, std::memory_order_relaxed);
        context_.metrics.stream_messages_on_turns.fetch_add(1, std::memory_order_relaxed);
      }
    }
    if (!here) pump();
  }
  if (here) {
    const auto start = std::chrono::steady_clock::now();
    handle_request();
    context_.scheduler.direct_requests().spend(std::chrono::steady_clock::now() - start);
  } else if (ok) {
    // Outside our lock: the scheduler takes its own lock and then ours (via take()).
    context_.scheduler.notify(shared_from_this(), 1);
  }
}

void BrickStream::handle_request() {
  std::size_t added = 0;
  {
    std::lock_guard lock(mutex_);
    if (!cancelled_ && !shutting_down_ && !finished_) {
      request_.Clear();
      const grpc::Status parsed =
          grpc::SerializationTraits<v1::BrickRequest>::Deserialize(&unhandled_request_, &request_);
      if (parsed.ok()) {
        added = accept_request();
      } else {
        const std::string why = parsed.error_message().empty()
                                    ? std::string()
                                    : " (" + quoted_text(parsed.error_message()) + ")";
        add_request_error(
            grpc::StatusCode::INVALID_ARGUMENT,
            "request message is not a soltex.v1.BrickRequest" + why + "; nothing in it was queued");
      }
    }
    unhandled_request_.Clear();
    request_unhandled_ = false;
    pump();
  }
  context_.scheduler.notify(shared_from_this(), added);
}

void BrickStream::register_textures() {
  const std::string& client = lease_->usage().client;
  for (const v1::RegisterTextureRequest& texture : request_.textures()) {
    try {
      TexturePin pin = register_texture(context_.registry, texture, client);
      context_.metrics.register_requests.fetch_add(1, std::memory_order_relaxed);
      const uint64_t id = pin.texture()->id;
      pins_.try_emplace(id, std::move(pin));  // already held: the extra pin is let go
    } catch (const RegistrationError& e) {
      add_request_error(e.code(), std::string("texture on the stream refused: ") + e.what(),
                        id_of_refused(texture));
      if (e.code() == grpc::StatusCode::RESOURCE_EXHAUSTED) {
        context_.refusals.refused(client, "texture on stream " + std::to_string(id_) + " from " +
                                              client + " refused: " + e.what());
      }
    }
  }
}

TexturePtr BrickStream::use_texture(uint64_t id) {
  if (const auto it = pins_.find(id); it != pins_.end()) return it->second.texture();
  TexturePin pin = context_.registry.pin(id);
  if (!pin) return nullptr;
  TexturePtr texture = pin.texture();
  pins_.emplace(id, std::move(pin));
  return texture;
}

std::size_t BrickStream::accept_request() {
  const StreamLimits& limits = context_.limits;
  register_textures();
  if (request_.accept_codecs_size() > 0) {
    for (int c : request_.accept_codecs()) {
      if (auto codec = codec_from_proto(static_cast<v1::Codec>(c))) {
        codec_ = *codec;
        break;
      }
    }
  }
  for (const v1::BrickKey& cancel : request_.cancel()) {
    const BrickKey key = from_proto(cancel);
    if (queue_.cancel(key)) {
      context_.metrics.bricks_cancelled.fetch_add(1, std::memory_order_relaxed);
      count_queued(-1);
    }
  }
  if (static_cast<uint32_t>(request_.want_size()) > limits.max_keys_per_request) {
    add_request_error(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      "request wants " + std::to_string(request_.want_size()) +
                          " bricks; at most " + std::to_string(limits.max_keys_per_request) +
                          " per request (max_keys_per_request); none were queued");
    return 0;
  }
  std::size_t added = 0;
  const auto now = std::chrono::steady_clock::now();
  seen_keys_.clear();
  seen_set_.clear();
  TexturePtr texture;  // consecutive keys usually name the same texture
  for (const v1::BrickWant& want : request_.want()) {
    const v1::BrickKey& k = want.key();
    if (!texture || texture->id != k.texture_id()) texture = use_texture(k.texture_id());
    if (!texture) {
      add_error(k, grpc::StatusCode::NOT_FOUND,
                "texture " + texture_id_hex(k.texture_id()) +
                    " is not registered on this server (call RegisterTexture first, or send it "
                    "in the request's textures; an unused texture may have been evicted)");
      continue;
    }
    const std::optional<BrickKey> key = admitted_key(k, want.priority(), texture->layout);
    if (!key) continue;
    if (answer_from_cache(*key, now)) continue;
    WorkItem item;
    item.key = *key;
    item.priority = want.priority();
    item.codec = codec_;
    item.texture = texture;
    item.enqueued = now;
    if (queue_.push(std::move(item)) == WorkQueue::Push::added) {
      ++added;
      context_.metrics.bricks_requested.fetch_add(1, std::memory_order_relaxed);
      count_queued(1);
    }
  }
  return added;
}

bool BrickStream::first_in_request(const BrickKey& key) {
  // Most messages carry a few keys: a scan of those seen costs less than hashing into a set,
  // whose nodes are allocated per key. Past kScannedKeys the set takes over.
  constexpr std::size_t kScannedKeys = 32;
  if (seen_set_.empty()) {
    if (std::find(seen_keys_.begin(), seen_keys_.end(), key) != seen_keys_.end()) return false;
    if (seen_keys_.size() < kScannedKeys) {
      seen_keys_.push_back(key);
      return true;
    }
    seen_set_.insert(seen_keys_.begin(), seen_keys_.end());
  }
  return seen_set_.insert(key).second;
}

std::optional<BrickKey> BrickStream::admitted_key(const v1::BrickKey& k, int32_t priority,
                                                  const BrickLayout& layout) {
  const StreamLimits& limits = context_.limits;
  if (k.level() > static_cast<uint32_t>(layout.coarsest_level())) {
    add_error(k, grpc::StatusCode::OUT_OF_RANGE,
              describe(k) + ": level " + std::to_string(k.level()) + " is outside [0, " +
                  std::to_string(layout.coarsest_level()) + "]");
    return std::nullopt;
  }
  const int level = static_cast<int>(k.level());
  if (!layout.contains(level, {k.x(), k.y(), k.z()})) {
    add_error(k, grpc::StatusCode::OUT_OF_RANGE,
              describe(k) + ": brick coordinates must be in [0, " +
                  std::to_string(layout.bricks_per_axis(level) - 1) + "] at level " +
                  std::to_string(level));
    return std::nullopt;
  }
  // A key wanted again in the same message is the same brick: sent once, whether it is
  // queued, taken by a worker meanwhile, or answered from the cache, and never refused for
  // the room its first copy took.
  const BrickKey key{k.texture_id(), level, {k.x(), k.y(), k.z()}};
  if (!first_in_request(key)) return std::nullopt;
  const bool client_full = lease_->usage().queued.load(std::memory_order_relaxed) >=
                           static_cast<int64_t>(limits.max_queued_per_client);
  const bool stream_full = owed() >= limits.max_queued_per_stream;
  // Asked again while still queued: merged with the first ask (its priority raised), which
  // takes no more room, so no queue bound refuses it. Merged here, under the queue's lock: a
  // worker may take the key at any moment, and a later push would queue it again.
  if ((client_full || stream_full) && queue_.merge(key, priority)) return std::nullopt;
  if (client_full) {
    refuse_over_queue_bound(k, "client " + lease_->usage().client + " has " +
                                   std::to_string(limits.max_queued_per_client) +
                                   " bricks queued over its streams (max_queued_per_client)");
    return std::nullopt;
  }
  if (stream_full) {
    refuse_over_queue_bound(k, "stream queue is full (" +
                                   std::to_string(limits.max_queued_per_stream) +
                                   " bricks, max_queued_per_stream)");
    return std::nullopt;
  }
  return key;
}

bool BrickStream::answer_from_cache(const BrickKey& key,
                                    std::chrono::steady_clock::time_point now) {
  EncodedBrickPtr hit = context_.producer.cached(key, codec_);
  if (!hit) return false;
  // A cache hit needs no worker: it goes straight to the outbox, where the request's other
  // hits join it in one message, without a thread hand-off per brick.
  if (queue_.cancel(key)) {
    count_queued(-1);  // asked for before and still queued: sent now instead
  } else {
    context_.metrics.bricks_requested.fetch_add(1, std::memory_order_relaxed);
  }
  add_to_outbox(std::move(hit), now, now);
  return true;
}

std::function<void()> BrickStream::take() {
  // A request first: its cancels and coarse levels decide what the bricks after it are.
  if (request_queued_.exchange(false, std::memory_order_relaxed)) {
    return [self = shared_from_this()] { self->handle_request(); };
  }
  // The client reads slower than its bricks are made: they wait in the queue, as keys, until
  // a write makes room (on_write_done() hands the stream back to the scheduler).
  if (unsent_full()) {
    throttled_.store(true, std::memory_order_relaxed);
    return {};
  }
  // More streams wait than there are workers (the same test as hold_back()'s): this stream's
  // next turn is far off, so this turn makes a run of its bricks, to share one message.
  const bool crowded =
      context_.scheduler.waiting_sources() > static_cast<std::size_t>(context_.scheduler.threads());
  const std::size_t run = crowded ? std::max<std::size_t>(context_.limits.run_bricks, 1) : 1;
  std::vector<WorkItem> items;
  while (items.size() < run) {
    std::optional<WorkItem> item = queue_.pop();
    if (!item) break;
    count_queued(-1);
    items.push_back(std::move(*item));
  }
  if (items.empty()) return {};
  return [self = shared_from_this(), items = std::move(items)]() mutable {
    const bool in_run = items.size() > 1;
    if (in_run) self->begin_run(items.size());
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (in_run && i > 0 &&
          std::chrono::steady_clock::now() - start >= self->context_.limits.run_time) {
        self->give_back({items.begin() + static_cast<std::ptrdiff_t>(i), items.end()});
        break;
      }
      const WorkItem& item = items[i];
      if (self->let_go_if_gone(in_run)) continue;  // cancelled mid-run: none of the rest is wanted
      // Measured here, not when the run was taken: a run's later bricks wait on this worker
      // behind its earlier ones, and that wait belongs to no other stage.
      self->context_.metrics.record(BrickStage::queue_wait,
                                    std::chrono::steady_clock::now() - item.enqueued);
      self->context_.producer.produce(item, [self, item, in_run](const EncodedBrickPtr& brick) {
        self->deliver(item, brick, in_run);
      });
    }
  };
}

void BrickStream::give_back(std::span<WorkItem> items) {
  std::size_t queued = 0;
  {
    std::lock_guard lock(mutex_);
    for (WorkItem& item : items) {
      --run_unmade_;
      if (queue_.give_back(std::move(item))) {
        ++queued;
      } else {
        // Asked for again meanwhile and queued as that: this one is let go, as cancelled.
        context_.metrics.bricks_cancelled.fetch_add(1, std::memory_order_relaxed);
      }
    }
    count_queued(static_cast<int64_t>(queued));
    pump();  // the run's message no longer waits for these
  }
  // Outside our lock: the scheduler takes its own lock and then ours (via take()).
  context_.scheduler.notify(shared_from_this(), queued);
}

void BrickStream::add_to_outbox(EncodedBrickPtr brick,
                                std::chrono::steady_clock::time_point enqueued,
                                std::chrono::steady_clock::time_point ready) {
  unsent_bytes_.fetch_add(brick->payload().size(), std::memory_order_relaxed);
  outbox_.push_back({std::move(brick), std::nullopt, std::nullopt, enqueued, ready});
}

void BrickStream::begin_run(std::size_t bricks) {
  std::lock_guard lock(mutex_);
  run_unmade_ += bricks;
}

bool BrickStream::let_go_if_gone(bool in_run) {
  std::lock_guard lock(mutex_);
  if (!cancelled_ && !shutting_down_ && !finished_) return false;
  if (in_run) --run_unmade_;
  queue_.finished();
  context_.metrics.bricks_cancelled.fetch_add(1, std::memory_order_relaxed);
  pump();
  return true;
}

void BrickStream::deliver(const WorkItem& item, const EncodedBrickPtr& brick, bool in_run) {
  std::lock_guard lock(mutex_);
  if (in_run) --run_unmade_;
  queue_.finished();
  if (brick) {
    add_to_outbox(brick, item.enqueued, std::chrono::steady_clock::now());
  } else {
    add_error(to_proto(item.key), grpc::StatusCode::INTERNAL,
              "evaluating " + describe(to_proto(item.key)) + " failed (see the server log)");
  }
  pump();
}

bool BrickStream::held_for_run() const {
  // A run's bricks share one message, however long the run takes on a loaded machine: the run
  // is bounded (run_bricks), and its last delivery sends the message, so no timer is needed.
  return run_unmade_ > 0 && outbox_.size() < context_.limits.coalesce_bricks && !shutting_down_;
}

bool BrickStream::hold_back() const {
  const StreamLimits& limits = context_.limits;
  // Only while more of the stream's bricks are coming soon: one is being made now, or some are
  // queued and the workers go round few enough streams to reach this one shortly. Among many
  // busy streams a held message would only wait out its timer (and wake the timer thread).
  // pump_when_wait_ends() bounds the wait.
  const std::size_t queued = queue_.size();
  const bool turn_soon = queued > 0 && context_.scheduler.waiting_sources() <=
                                           static_cast<std::size_t>(context_.scheduler.threads());
  const bool more_coming = queue_.taken() > 0 || turn_soon;
  return more_coming && outbox_.size() < limits.coalesce_bricks && !shutting_down_ &&
         std::chrono::steady_clock::now() - outbox_.front().ready < limits.coalesce_wait;
}

void BrickStream::pump_when_wait_ends() {
  if (coalesce_timer_armed_) return;
  coalesce_timer_armed_ = true;
  coalesce_timer_.expires_at(outbox_.front().ready + context_.limits.coalesce_wait);
  coalesce_timer_.async_wait([self = shared_from_this()](const boost::system::error_code&) {
    std::lock_guard lock(self->mutex_);
    self->coalesce_timer_armed_ = false;
    self->pump();
  });
}

std::size_t BrickStream::owed() const {
  return queue_.outstanding() + outbox_.size();
}

void BrickStream::add_error(const v1::BrickKey& key, grpc::StatusCode code, std::string message) {
  v1::BrickError error;
  *error.mutable_key() = key;
  error.set_code(static_cast<int32_t>(code));
  error.set_message(std::move(message));
  context_.metrics.count_error(static_cast<int>(code));
  const auto now = std::chrono::steady_clock::now();
  outbox_.push_back({nullptr, std::move(error), std::nullopt, now, now});
}

void BrickStream::refuse_over_queue_bound(const v1::BrickKey& k, const std::string& why) {
  add_error(k, grpc::StatusCode::RESOURCE_EXHAUSTED, describe(k) + ": " + why);
  const std::string& client = lease_->usage().client;
  context_.refusals.refused(
      client, "bricks on stream " + std::to_string(id_) + " from " + client + " refused: " + why);
}

void BrickStream::add_request_error(grpc::StatusCode code, std::string message,
                                    uint64_t texture_id) {
  v1::RequestError error;
  error.set_code(static_cast<int32_t>(code));
  error.set_message(std::move(message));
  error.set_texture_id(texture_id);
  context_.metrics.count_error(static_cast<int>(code));
  const auto now = std::chrono::steady_clock::now();
  outbox_.push_back({nullptr, std::nullopt, std::move(error), now, now});
}

void BrickStream::write_outbox() {
  const StreamLimits& limits = context_.limits;
  batch_slices_.clear();
  batch_errors_.Clear();
  batch_enqueued_.clear();
  batch_ready_.clear();
  std::size_t bytes = 0;
  uint32_t bricks = 0;
  while (!outbox_.empty()) {
    Outgoing& next = outbox_.front();
    if (next.brick) {
      const std::size_t size = next.brick->payload().size();
      if (bricks >= limits.max_batch_bricks ||
          (bricks > 0 && bytes + size > limits.max_batch_bytes)) {
        break;
      }
      batch_slices_.push_back(element_to_send(*next.brick, context_.faults));
      ++bricks;
      bytes += size;
      batch_enqueued_.push_back(next.enqueued);
      batch_ready_.push_back(next.ready);
    } else if (next.error) {
      *batch_errors_.add_errors() = std::move(*next.error);
    } else {
      *batch_errors_.add_request_errors() = std::move(*next.request_error);
    }
    outbox_.pop_front();
  }
  // The errors' fields (2 and 3) after the bricks' (1): the bytes protobuf would write for the
  // whole message.
  const auto errors =
      static_cast<uint64_t>(batch_errors_.errors_size() + batch_errors_.request_errors_size());
  if (errors > 0) batch_slices_.emplace_back(batch_errors_.SerializeAsString());
  grpc::ByteBuffer message(batch_slices_.data(), batch_slices_.size());
  batch_.Swap(&message);
  batch_slices_.clear();  // the message holds its own references
  writing_ = true;
  writing_bytes_ = bytes;
  ++batches_sent_;
  bricks_sent_ += bricks;
  bytes_sent_ += bytes;
  errors_sent_ += errors;
  context_.metrics.bricks_served.fetch_add(bricks, std::memory_order_relaxed);
  context_.metrics.bytes_served.fetch_add(bytes, std::memory_order_relaxed);
  const auto now = std::chrono::steady_clock::now();
  for (const auto& enqueued : batch_enqueued_) {
    context_.metrics.brick_latency_ns.record(static_cast<uint64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(now - enqueued).count()));
  }
  for (const auto& ready : batch_ready_) {
    context_.metrics.record(BrickStage::outbox_wait, now - ready);
  }
  write_started_ = now;
  reactor_->StartWrite(&batch_);
}

void BrickStream::pump() {
  if (finished_ || reactor_ == nullptr) return;
  const StreamLimits& limits = context_.limits;

  const bool can_write = !writing_ && !outbox_.empty() && !cancelled_;
  const bool held_by_run = can_write && held_for_run();
  const bool held = held_by_run || (can_write && hold_back());
  if (held && !held_by_run) pump_when_wait_ends();
  if (can_write && !held) write_outbox();

  // Backpressure: read on while a whole request would still fit, counting every brick the
  // stream owes: queued, being produced, and made but not yet written. Past that, read on only
  // while the client takes what it is sent (no more than a request's worth waits in the
  // outbox), so that its cancels are applied and wants past the bound are refused, while a
  // client that stops reading does not make the server hold answers without bound.
  const bool fits = owed() + limits.max_keys_per_request <= limits.max_queued_per_stream;
  const bool taken = !unsent_full() && outbox_.size() < limits.max_keys_per_request;
  const bool room = fits || taken;
  if (!reading_ && !request_unhandled_ && !reads_done_ && !draining_ && !shutting_down_ &&
      !cancelled_ && room) {
    reading_ = true;
    reactor_->StartRead(&request_bytes_);
  }

  const bool idle = !writing_ && outbox_.empty() && queue_.drained() && !request_unhandled_;
  grpc::Status status;
  bool finish = false;
  if (cancelled_) {
    finish = !writing_;
    status = grpc::Status(grpc::StatusCode::CANCELLED, "stream cancelled");
  } else if (shutting_down_ && !writing_) {
    finish = true;
    status = grpc::Status(grpc::StatusCode::UNAVAILABLE, "soltexd is shutting down");
  } else if (reads_done_ && idle) {
    finish = true;
  } else if (draining_ && idle) {
    finish = true;
    status = grpc::Status(grpc::StatusCode::UNAVAILABLE,
                          request_after_drain_
                              ? "soltexd is shutting down; every brick asked for before then "
                                "was sent, and what was sent since was not read"
                              : "soltexd is shutting down; every brick asked for was sent");
  }
  if (finish) {
    finished_ = true;
    coalesce_timer_.cancel();  // nothing more to send: let go of the stream now, not at the wait
    spdlog::info(
        "stream {} from {} closed ({}): {} bricks in {} messages, {} bytes, {} errors in {:.1f} s",
        id_, peer_, status.ok() ? "OK" : status.error_message(), bricks_sent_, batches_sent_,
        bytes_sent_, errors_sent_,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - opened_).count());
    reactor_->Finish(status);
  }
}

void BrickStream::on_write_done(bool ok) {
  std::size_t resumed = 0;
  {
    std::lock_guard lock(mutex_);
    context_.metrics.record(BrickStage::write, std::chrono::steady_clock::now() - write_started_);
    writing_ = false;
    unsent_bytes_.fetch_sub(writing_bytes_, std::memory_order_relaxed);
    writing_bytes_ = 0;
    if (!ok) cancelled_ = true;  // the client is gone; OnCancel or OnDone follows
    pump();
    if (!unsent_full() && throttled_.exchange(false, std::memory_order_relaxed)) {
      resumed = queue_.size();
    }
  }
  // Outside our lock: the scheduler takes its own lock and then ours (via take()).
  context_.scheduler.notify(shared_from_this(), resumed);
}

void BrickStream::on_cancel() {
  std::lock_guard lock(mutex_);
  cancelled_ = true;
  drop_queue();
  pump();
}

void BrickStream::drain() {
  std::lock_guard lock(mutex_);
  draining_ = true;
  pump();
}

void BrickStream::shut_down() {
  std::lock_guard lock(mutex_);
  shutting_down_ = true;
  drop_queue();
  pump();
}

void BrickStream::on_done() {
  std::lock_guard lock(mutex_);
  reactor_ = nullptr;
  coalesce_timer_.cancel();
  lease_->release();
  pins_.clear();  // its textures may be evicted now; queued work holds its own references
}

}  // namespace soltex::server
