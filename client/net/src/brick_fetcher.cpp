#include "soltex/net/brick_fetcher.h"

#include <grpcpp/grpcpp.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <iterator>
#include <optional>
#include <stdexcept>

#include "soltex/common/brick_codec.h"
#include "soltex/common/check.h"
#include "soltex/common/texture_id.h"
#include "soltex/net/request_packer.h"
#include "soltex/spec_proto/brick_proto.h"
#include "soltex/spec_proto/spec_from_proto.h"
#include "soltex/v1/brick_service.grpc.pb.h"
#include "warning_throttle.h"

namespace soltex::net {
namespace {

// How soon a waiting supervisor sees that the fetcher is stopping.
constexpr auto kStopCheck = std::chrono::milliseconds(50);

// The pause after the server refused every want it was sent over a queue bound, doubled for
// each refusal in a row up to the most, and back to the first once a brick arrives.
constexpr std::chrono::milliseconds kFirstRefusalBackoff{10};
constexpr std::chrono::milliseconds kMaxRefusalBackoff{1000};

// `line` through `throttle`, with how many like it were held back before it.
template <typename... Args>
void throttled_warning(WarningThrottle& throttle, fmt::format_string<Args...> line,
                       Args&&... args) {
  uint64_t held_back = 0;
  if (!throttle.allow(held_back)) return;
  const std::string text = fmt::format(line, std::forward<Args>(args)...);
  if (held_back == 0) {
    spdlog::warn("{}", text);
  } else {
    spdlog::warn("{} ({} more like it not logged)", text, held_back);
  }
}

// The codes a server answers about a texture itself: another texture may still register.
bool refuses_the_texture_alone(grpc::StatusCode code) {
  return code == grpc::StatusCode::INVALID_ARGUMENT ||
         code == grpc::StatusCode::RESOURCE_EXHAUSTED ||
         code == grpc::StatusCode::FAILED_PRECONDITION || code == grpc::StatusCode::OUT_OF_RANGE;
}

}  // namespace

struct BrickFetcher::Warnings {
  WarningThrottle refused, corrupt;
};

struct BrickFetcher::Channel {
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<v1::BrickService::Stub> stub;
};

struct BrickFetcher::Stream {
  grpc::ClientContext info_context;  // the GetServerInfo before the stream opens
  grpc::ClientContext context;
  std::mutex write_mutex;  // Write and Finish never overlap
  std::unique_ptr<grpc::ClientReaderWriter<v1::BrickRequest, v1::BrickBatch>> call;
};

BrickFetcher::BrickFetcher(std::string server_address, BrickCache& cache, FetcherOptions options)
    : address_(std::move(server_address)),
      cache_(cache),
      options_(options),
      channel_(std::make_unique<Channel>()),
      warnings_(std::make_unique<Warnings>()),
      in_flight_bound_(options.max_in_flight),
      congestion_bound_(options.max_in_flight),
      codec_(options.codec) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(64 << 20);
  // Reconnect promptly after a server restart; our own backoff paces the streams.
  args.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 100);
  args.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, static_cast<int>(options_.max_backoff.count()));
  channel_->channel = open_channel(address_, options_.security, args);
  channel_->stub = v1::BrickService::NewStub(channel_->channel);
  supervisor_ = std::thread([this] { supervise(); });
  writer_ = std::thread([this] { write_loop(); });
}

BrickFetcher::~BrickFetcher() {
  std::shared_ptr<Stream> stream, opening;
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    stream = stream_;
    opening = opening_;
  }
  if (stream) stream->context.TryCancel();
  if (opening) {
    opening->info_context.TryCancel();
    opening->context.TryCancel();
  }
  changed_.notify_all();
  writer_.join();
  supervisor_.join();
  for (auto [throttle, kind] : {std::pair{&warnings_->refused, "refusal"},
                                std::pair{&warnings_->corrupt, "corrupt-brick"}}) {
    if (const uint64_t n = throttle->take_held_back(); n > 0) {
      spdlog::warn("{} more {} warnings from {} were not logged", n, kind, address_);
    }
  }
}

uint64_t BrickFetcher::register_texture(const TextureSpec& spec, const Volume& volume,
                                        int brick_size, const MipSettings& mip) {
  v1::RegisterTextureRequest request;
  *request.mutable_spec() = soltex::to_proto(spec);
  *request.mutable_volume() = soltex::to_proto(volume);
  request.set_brick_size(static_cast<uint32_t>(brick_size));
  request.set_mip_mode(to_proto(mip.mode));
  request.set_supersample(static_cast<uint32_t>(mip.supersample));
  grpc::ClientContext context;
  authorize(options_.security, context);
  context.set_deadline(std::chrono::system_clock::now() + options_.register_timeout);
  context.set_wait_for_ready(true);
  v1::TextureHandle handle;
  const grpc::Status status = channel_->stub->RegisterTexture(&context, request, &handle);
  if (!status.ok()) {
    const std::string why =
        "registering the texture with " + address_ + " failed: " + status.error_message();
    if (refuses_the_texture_alone(status.error_code())) throw TextureRefused(why);
    throw std::runtime_error(why);
  }
  std::lock_guard lock(mutex_);
  // Registered again after a stream's refusal (a scene prepared anew): another chance.
  refused_ids_.erase(handle.id());
  if (registrations_.emplace(handle.id(), request.SerializeAsString()).second && stream_) {
    unsent_registrations_.push_back(handle.id());
  }
  // The coarsest level is every lookup's last resort: keep it resident.
  cache_.pin_levels(handle.id(), static_cast<int>(handle.levels()) - 1);
  return handle.id();
}

void BrickFetcher::supervise() {
  auto backoff = options_.initial_backoff;
  bool first = true;
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      if (stopping_) return;
    }
    {
      auto stream = std::make_shared<Stream>();
      authorize(options_.security, stream->context);
      {
        std::lock_guard lock(mutex_);
        if (stopping_) return;
        opening_ = stream;
      }
      learn_bounds(*stream);
      stream->call = channel_->stub->StreamBricks(&stream->context);
      {
        std::lock_guard lock(mutex_);
        opening_.reset();
        if (stopping_) return;
        stream_ = stream;
        stats_.connected = true;
        resend_ = true;  // with every texture: this server may never have seen them
        unsent_registrations_.clear();
        if (!first) ++stats_.reconnects;
      }
      changed_.notify_all();
      if (options_.on_event) options_.on_event(FetchEvent::stream_opened, 0);
      v1::BrickBatch batch;
      bool received_any = false;
      while (stream->call->Read(&batch)) {
        received_any = true;
        backoff = options_.initial_backoff;
        on_batch(batch);
      }
      {
        std::lock_guard writes(mutex_);
        stream_.reset();
        stats_.connected = false;
      }
      grpc::Status status;
      {
        // Take the stream from the writer; if it is stuck in a Write waiting on flow control,
        // cancel the call to release it (the status then reads CANCELLED).
        std::unique_lock writing(stream->write_mutex, std::try_to_lock);
        if (!writing.owns_lock()) {
          stream->context.TryCancel();
          writing.lock();
        }
        status = stream->call->Finish();
      }
      {
        std::lock_guard lock(mutex_);
        if (stopping_) return;
      }
      if (!status.ok() || !received_any) {
        spdlog::warn("brick stream to {} ended ({}); reconnecting in {} ms", address_,
                     status.ok() ? "closed" : status.error_message(), backoff.count());
      }
    }
    first = false;
    if (!wait_to_reconnect(backoff)) return;
    backoff = std::min(backoff * 2, options_.max_backoff);
  }
}

void BrickFetcher::learn_bounds(Stream& stream) {
  authorize(options_.security, stream.info_context);
  stream.info_context.set_deadline(std::chrono::system_clock::now() + options_.register_timeout);
  v1::ServerInfo info;
  if (!channel_->stub->GetServerInfo(&stream.info_context, {}, &info).ok()) return;
  const v1::Limits& limits = info.limits();
  std::lock_guard lock(mutex_);
  if (limits.max_message_bytes() > 0) bounds_.max_bytes = limits.max_message_bytes();
  if (limits.max_keys_per_request() > 0) bounds_.max_wants = limits.max_keys_per_request();
  in_flight_bound_ = options_.max_in_flight;
  for (const uint32_t queued : {limits.max_queued_per_stream(), limits.max_queued_per_client()}) {
    if (queued > 0) in_flight_bound_ = std::min<std::size_t>(in_flight_bound_, queued);
  }
  congestion_bound_ = in_flight_bound_;
}

bool BrickFetcher::wait_to_reconnect(std::chrono::milliseconds backoff) {
  // Waiting on the channel rather than a timer: it asks gRPC to connect and returns as soon
  // as it has, so a restarted server is reached at once. After a sleep instead, a fail-fast
  // call found the channel still failing (gRPC's own reconnect waits for a call to ask for
  // it) and every retry failed until the backoff was seconds long.
  if (channel_->channel->GetState(false) == GRPC_CHANNEL_READY) {
    // A server that is up but ended the stream (refused it: no token, too many streams) gets
    // the whole backoff: reconnecting at once would spin.
    std::unique_lock lock(mutex_);
    return !changed_.wait_for(lock, backoff, [this] { return stopping_; });
  }
  const auto deadline = std::chrono::system_clock::now() + backoff;
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (stopping_) return false;
    }
    const auto now = std::chrono::system_clock::now();
    if (now >= deadline) return true;
    // In slices, so that a stop is seen within kStopCheck.
    if (channel_->channel->WaitForConnected(std::min(deadline, now + kStopCheck))) return true;
  }
}

void BrickFetcher::on_batch(v1::BrickBatch& batch) {
  std::vector<std::pair<BrickKey, std::string>> payloads;
  payloads.reserve(static_cast<std::size_t>(batch.bricks_size()));
  for (auto& brick : *batch.mutable_bricks()) {
    payloads.emplace_back(from_proto(brick.key()), std::move(*brick.mutable_payload()));
  }
  receive(payloads);
  if (options_.on_event) options_.on_event(FetchEvent::batch_received, payloads.size());
  if (batch.errors_size() > 0 || batch.request_errors_size() > 0) {
    std::lock_guard lock(mutex_);
    // A texture refused on the stream first: the NOT_FOUND answers to its wants follow it.
    for (const auto& error : batch.request_errors()) {
      if (error.texture_id() != 0) {
        refuse_texture(error.texture_id(), error.message());
        continue;
      }
      ++stats_.errors;
      throttled_warning(warnings_->refused, "request refused: {}", error.message());
    }
    for (const auto& error : batch.errors()) {
      const BrickKey key = from_proto(error.key());
      in_flight_.erase(key);
      if (error.code() == static_cast<int32_t>(grpc::StatusCode::RESOURCE_EXHAUSTED)) {
        defer(key);
        continue;
      }
      failed_.insert(key);
      if (refused_ids_.contains(key.texture)) continue;  // said once, with the texture
      ++stats_.errors;
      throttled_warning(warnings_->refused, "brick refused: {}", error.message());
    }
  }
  changed_.notify_all();
}

void BrickFetcher::receive(const std::vector<std::pair<BrickKey, std::string>>& payloads) {
  for (const auto& [key, payload] : payloads) {
    std::optional<CachedBrick> brick;
    std::size_t codec = std::size(stats_.decode_seconds);  // none: not decoded
    double decode_seconds = 0.0;
    std::size_t decoded_bytes = 0;
    try {
      const auto start = std::chrono::steady_clock::now();
      const DecodedBrick decoded =
          decode_brick(std::span(reinterpret_cast<const uint8_t*>(payload.data()), payload.size()));
      decode_seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      // Converted here, outside every lock: inserting it is then only bookkeeping.
      brick.emplace(decoded.brick_size, decoded.channels, decoded.samples);
      // A brick that decoded has a whole header; its byte 7 is the codec (docs/PROTOCOL.md).
      codec = static_cast<uint8_t>(payload[7]);
      decoded_bytes = decoded.samples.size();
    } catch (const CodecError& e) {
      throttled_warning(warnings_->corrupt, "corrupt brick from {}: {}", address_, e.what());
    }
    std::unique_lock lock(mutex_);
    stats_.bytes += payload.size();
    if (codec < std::size(stats_.decode_seconds)) {
      stats_.decode_seconds[codec] += decode_seconds;
      stats_.decoded_bytes[codec] += decoded_bytes;
    }
    if (brick && holding_) {
      // Arrived, so no longer counted against the in-flight bound; still pending (idle() is
      // false) until released.
      in_flight_.erase(key);
      held_keys_.insert(key);
      held_.emplace_back(key, std::move(*brick));
      continue;
    }
    if (brick) {
      lock.unlock();
      cache_.insert(key, std::move(*brick));
      lock.lock();
    }
    in_flight_.erase(key);
    if (brick) {
      ++stats_.received;
      refetches_.erase(key);
      congestion_bound_ = std::min(congestion_bound_ + 1, in_flight_bound_);
      refusal_backoff_ = kFirstRefusalBackoff;
    } else if (++refetches_[key] <= options_.max_refetches) {
      // Damaged on the way: ask again, first in line (unless a frame asked for it again
      // meanwhile and it waits already).
      ++stats_.corrupt;
      wait_first(key);
    } else {
      failed_.insert(key);
      ++stats_.errors;
    }
  }
}

void BrickFetcher::hold_arrivals(bool hold) {
  std::vector<std::pair<BrickKey, CachedBrick>> held;
  {
    std::lock_guard lock(mutex_);
    holding_ = hold;
    if (hold) return;
    held.swap(held_);
  }
  if (held.empty()) return;
  // Inserted outside the lock; the keys stay in held_keys_ meanwhile, so these bricks count
  // as pending until they count as received.
  for (auto& [key, brick] : held) cache_.insert(key, std::move(brick));
  {
    std::lock_guard lock(mutex_);
    for (const auto& [key, brick] : held) {
      held_keys_.erase(key);
      refetches_.erase(key);
      ++stats_.received;
    }
  }
  changed_.notify_all();
}

void BrickFetcher::want(std::vector<BrickWant> wants) {
  std::sort(wants.begin(), wants.end(), fetched_before);
  std::unordered_set<BrickKey, BrickKeyHash> wanted;
  std::vector<BrickWant> fresh;
  for (const BrickWant& w : wants) {
    if (!wanted.insert(w.key).second) continue;  // duplicate
    fresh.push_back(w);
  }
  {
    std::lock_guard lock(mutex_);
    // What is in flight and no frame wants any more is stale: cancel it.
    for (auto it = in_flight_.begin(); it != in_flight_.end();) {
      if (!wanted.contains(*it)) {
        to_cancel_.push_back(*it);
        ++stats_.cancelled;
        it = in_flight_.erase(it);
      } else {
        ++it;
      }
    }
    waiting_.clear();
    waiting_keys_.clear();
    for (const BrickWant& w : fresh) {
      if (in_flight_.contains(w.key) || held_keys_.contains(w.key) || failed_.contains(w.key) ||
          refused_ids_.contains(w.key.texture) || cache_.contains(w.key)) {
        continue;
      }
      add_waiting(w);  // fresh holds each key once
    }
  }
  changed_.notify_all();
}

void BrickFetcher::want_early(std::vector<BrickWant> wants) {
  std::sort(wants.begin(), wants.end(), fetched_before);
  bool added = false;
  {
    std::lock_guard lock(mutex_);
    for (const BrickWant& w : wants) {
      if (in_flight_.contains(w.key) || held_keys_.contains(w.key) || failed_.contains(w.key) ||
          refused_ids_.contains(w.key.texture) || cache_.contains(w.key)) {
        continue;
      }
      // A key another render thread found first is waiting already.
      if (add_waiting(w)) added = true;
    }
  }
  if (added) changed_.notify_all();
}

bool BrickFetcher::add_waiting(const BrickWant& want) {
  if (!waiting_keys_.insert(want.key).second) return false;
  waiting_.push_back(want);
  return true;
}

void BrickFetcher::wait_first(const BrickKey& key) {
  if (waiting_keys_.insert(key).second) waiting_.insert(waiting_.begin(), BrickWant{key, ~0u});
}

std::size_t BrickFetcher::wants_bound() const {
  if (std::chrono::steady_clock::now() < wants_paused_until_) return 0;
  return std::min(in_flight_bound_, congestion_bound_);
}

bool BrickFetcher::may_send_wants() const {
  return !waiting_.empty() && in_flight_.size() < wants_bound();
}

void BrickFetcher::defer(const BrickKey& key) {
  ++stats_.deferred;
  wait_first(key);
  // What the server holds now is about what it can hold: no more until bricks come back.
  congestion_bound_ = std::max<std::size_t>(in_flight_.size(), 1);
  if (in_flight_.empty()) {
    // Nothing of ours is in its queue: others fill it. Wait before asking again.
    wants_paused_until_ = std::chrono::steady_clock::now() + refusal_backoff_;
    refusal_backoff_ = std::min(refusal_backoff_ * 2, kMaxRefusalBackoff);
  }
}

void BrickFetcher::refuse_texture(uint64_t id, const std::string& reason) {
  if (!refused_ids_.insert(id).second) return;
  refused_textures_.emplace_back(id, reason);
  registrations_.erase(id);  // a later stream need not carry it
  std::erase_if(waiting_, [&](const BrickWant& w) {
    if (w.key.texture != id) return false;
    waiting_keys_.erase(w.key);
    return true;
  });
  std::erase_if(in_flight_, [&](const BrickKey& key) { return key.texture == id; });
}

std::vector<std::pair<uint64_t, std::string>> BrickFetcher::take_refused_textures() {
  std::lock_guard lock(mutex_);
  std::vector<std::pair<uint64_t, std::string>> taken;
  taken.swap(refused_textures_);
  return taken;
}

void BrickFetcher::write_loop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    const auto ready = [this] {
      return stopping_ || (stream_ && (resend_ || codec_changed_ || !to_cancel_.empty() ||
                                       !unsent_registrations_.empty() || may_send_wants()));
    };
    // A pause after refusals ends by itself: wake for it.
    while (!ready()) {
      if (!waiting_.empty() && std::chrono::steady_clock::now() < wants_paused_until_) {
        changed_.wait_until(lock, wants_paused_until_);
      } else {
        changed_.wait(lock);
      }
    }
    if (stopping_) return;
    std::shared_ptr<Stream> stream = stream_;
    std::vector<v1::BrickRequest> requests = pack_requests();
    // Write outside the lock: it may wait for flow control.
    lock.unlock();
    bool ok = true;
    {
      std::lock_guard writing(stream->write_mutex);
      for (const v1::BrickRequest& request : requests) {
        ok = stream->call->Write(request);
        if (!ok) break;
        if (options_.on_event) {
          options_.on_event(FetchEvent::request_written,
                            static_cast<std::size_t>(request.want_size()));
        }
      }
    }
    lock.lock();
    if (!ok && stream_ == stream) {
      // The stream is broken; the supervisor will notice on its read and reconnect.
      changed_.wait_for(lock, std::chrono::milliseconds(50));
    }
  }
}

std::vector<v1::BrickRequest> BrickFetcher::pack_requests() {
  RequestPacker packer(bounds_);
  const auto add_texture = [&](uint64_t id, const std::string& serialized) {
    // Larger than this server's messages: it was registered with another server (RegisterTexture
    // sends the same bytes). Its bricks are refused as unknown and drawn from what is resident.
    if (!packer.add_texture(serialized)) {
      throttled_warning(warnings_->refused,
                        "texture {:016x} ({} bytes) is larger than {} accepts in a message "
                        "({} bytes, max_message_bytes); not sent",
                        id, serialized.size(), address_, bounds_.max_bytes);
    }
  };
  if (resend_) {
    // A new stream, perhaps to another replica, knows nothing of the old one: send every
    // texture, then everything still in flight.
    for (const auto& [id, serialized] : registrations_) add_texture(id, serialized);
    // As many as this server's bounds allow (it may be another, with smaller ones); the rest
    // wait their turn.
    std::size_t resent = 0;
    for (auto it = in_flight_.begin(); it != in_flight_.end();) {
      if (resent < in_flight_bound_) {
        packer.add_want(to_proto(*it++), 0);
        ++resent;
      } else {
        wait_first(*it);
        it = in_flight_.erase(it);
      }
    }
    resend_ = false;
    codec_changed_ = true;
  } else {
    for (const uint64_t id : unsent_registrations_) {
      if (const auto it = registrations_.find(id); it != registrations_.end()) {
        add_texture(id, it->second);
      }
    }
  }
  unsent_registrations_.clear();
  if (codec_changed_) packer.add_codec(to_proto(codec_));
  codec_changed_ = false;
  for (const BrickKey& key : to_cancel_) packer.add_cancel(to_proto(key));
  to_cancel_.clear();
  std::size_t taken = 0;
  const std::size_t bound = wants_bound();
  while (taken < waiting_.size() && in_flight_.size() < bound) {
    const BrickWant& w = waiting_[taken++];
    waiting_keys_.erase(w.key);
    if (cache_.contains(w.key) || in_flight_.contains(w.key) || held_keys_.contains(w.key)) {
      continue;
    }
    in_flight_.insert(w.key);
    packer.add_want(to_proto(w.key),
                    static_cast<int32_t>(std::min<uint32_t>(w.screen_pixels, 1u << 30)));
    ++stats_.requested;
  }
  waiting_.erase(waiting_.begin(), waiting_.begin() + static_cast<std::ptrdiff_t>(taken));
  SOLTEX_DCHECK(waiting_keys_.size() == waiting_.size());
  return packer.take();
}

void BrickFetcher::set_codec(Codec codec) {
  {
    std::lock_guard lock(mutex_);
    if (codec == codec_) return;
    codec_ = codec;
    codec_changed_ = true;
  }
  changed_.notify_all();
}

bool BrickFetcher::nothing_pending() const {
  return waiting_.empty() && in_flight_.empty() && held_keys_.empty();
}

bool BrickFetcher::idle() const {
  std::lock_guard lock(mutex_);
  return nothing_pending();
}

bool BrickFetcher::wait_idle(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return changed_.wait_for(lock, timeout, [this] { return nothing_pending(); });
}

SourceStats BrickFetcher::stats() const {
  std::lock_guard lock(mutex_);
  SourceStats s = stats_;
  s.in_flight = in_flight_.size() + held_keys_.size();
  s.waiting = waiting_.size();
  return s;
}

std::chrono::microseconds BrickFetcher::measure_round_trip(std::chrono::milliseconds timeout) {
  const auto start = std::chrono::steady_clock::now();
  grpc::ClientContext context;
  authorize(options_.security, context);
  context.set_deadline(std::chrono::system_clock::now() + timeout);
  v1::ServerInfo info;
  const grpc::Status status = channel_->stub->GetServerInfo(&context, {}, &info);
  if (status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED) {
    throw std::runtime_error("server " + address_ + " did not answer within " +
                             std::to_string(timeout.count()) + " ms");
  }
  if (!status.ok()) {
    // Answered at once: refused (a token, TLS), or nothing listens there.
    throw std::runtime_error("server " + address_ +
                             (status.error_code() == grpc::StatusCode::UNAVAILABLE
                                  ? " cannot be reached: "
                                  : " refused this client: ") +
                             status.error_message());
  }
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() -
                                                               start);
}

}  // namespace soltex::net
