#include "load_stream.h"

#include <grpcpp/support/proto_buffer_reader.h>

#include <span>

#include "soltex/common/brick_codec.h"
#include "soltex/net/request_packer.h"
#include "soltex/spec_proto/brick_proto.h"

namespace soltex::load {
LoadStream::LoadStream(BrickStreamStub& stub, const Settings& settings,
                       std::unique_ptr<RequestMix> mix, LoadRecorder& recorder,
                       RequestBudget& budget, std::function<void()> on_done)
    : settings_(settings),
      mix_(std::move(mix)),
      recorder_(recorder),
      budget_(budget),
      on_done_(std::move(on_done)),
      stub_(stub) {}

void LoadStream::start() {
  if (settings_.security) net::authorize(*settings_.security, context_);
  stub_.PrepareBidiStreamingCall(&context_, kStreamBricksMethod, grpc::StubOptions(), this);
  AddHold();  // writes are also started from outside reactions (issue, close)
  StartRead(&read_);
  StartCall();
  Starts starts;
  {
    std::lock_guard lock(mutex_);
    const Clock::time_point now = Clock::now();
    for (int i = 0; i < settings_.in_flight; ++i) {
      if (!issue_locked(now)) break;
    }
    starts = next_starts_locked();
  }
  perform(starts);
}

bool LoadStream::issue(Clock::time_point intended) {
  Starts starts;
  bool taken;
  {
    std::lock_guard lock(mutex_);
    taken = issue_locked(intended);
    starts = next_starts_locked();
  }
  perform(starts);
  return taken;
}

void LoadStream::close() {
  Starts starts;
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
    starts = next_starts_locked();
  }
  perform(starts);
}

bool LoadStream::done() const {
  std::lock_guard lock(mutex_);
  return done_;
}

bool LoadStream::issue_locked(Clock::time_point intended) {
  if (closing_ || half_closed_ || reads_ended_) return false;
  const bool measured = recorder_.measured(intended);
  if (measured && !budget_.take()) {
    closing_ = true;
    return false;
  }
  const PlannedWant want =
      mix_->next([this](const BrickKey& key) { return outstanding_.contains(key); });
  recorder_.requested(measured, want.invalid);
  if (backlog_.size() + parked_count_ >= settings_.max_backlog) {
    recorder_.dropped_backlog();
    return true;
  }
  if (outstanding_.contains(want.key)) {
    park_locked({want, intended});
  } else {
    backlog_.push_back({want, intended});
  }
  return true;
}

void LoadStream::park_locked(Pending pending) {
  const BrickKey key = pending.want.key;
  parked_[key].push_back(std::move(pending));
  ++parked_count_;
}

void LoadStream::unpark_locked(const BrickKey& key) {
  const auto it = parked_.find(key);
  if (it == parked_.end()) return;
  // It has waited longer than anything in the backlog: it goes first.
  backlog_.push_front(std::move(it->second.front()));
  it->second.pop_front();
  --parked_count_;
  if (it->second.empty()) parked_.erase(it);
}

LoadStream::Starts LoadStream::next_starts_locked() {
  Starts starts;
  if (writing_ || half_closed_ || reads_ended_) return starts;
  write_.Clear();
  // The message's bytes as protobuf will count them: the texture and codec that go with the
  // wants, then each want, so that it stays within the server's max_message_bytes.
  std::size_t bytes = (texture_sent_ ? 0 : net::field_bytes(settings_.texture.ByteSizeLong())) +
                      net::RequestPacker::kCodecBytes;
  while (!backlog_.empty() &&
         static_cast<uint32_t>(write_.want_size()) < settings_.max_keys_per_request) {
    v1::BrickWant want;
    *want.mutable_key() = to_proto(backlog_.front().want.key);
    want.set_priority(backlog_.front().want.priority);
    const std::size_t want_bytes = net::field_bytes(want.ByteSizeLong());
    if (write_.want_size() > 0 && bytes + want_bytes > settings_.max_message_bytes) break;
    Pending next = std::move(backlog_.front());
    backlog_.pop_front();
    // An earlier request for the same key went out since this one was issued.
    if (!outstanding_.emplace(next.want.key, next.intended).second) {
      park_locked(std::move(next));
      continue;
    }
    *write_.add_want() = std::move(want);
    bytes += want_bytes;
  }
  if (write_.want_size() > 0) {
    write_.add_accept_codecs(settings_.codec);
    if (!texture_sent_) {
      *write_.add_textures() = settings_.texture;
      texture_sent_ = true;
    }
    writing_ = true;
    starts.write = true;
  } else if (closing_ && backlog_.empty() && parked_count_ == 0) {
    half_closed_ = true;
    starts.writes_done = true;
  }
  if (starts.any()) ++starting_;
  return starts;
}

void LoadStream::perform(Starts starts) {
  if (starts.write) StartWrite(&write_);
  if (starts.writes_done) StartWritesDone();
  bool release = false;
  {
    std::lock_guard lock(mutex_);
    if (starts.any()) --starting_;
    // Once nothing more will be written (half-closed, or the call is over) and no other
    // thread is about to start an operation, the call may end: drop our hold.
    if (!hold_released_ && starting_ == 0 && (half_closed_ || reads_ended_)) {
      hold_released_ = true;
      release = true;
    }
  }
  if (release) RemoveHold();
}

void LoadStream::OnWriteDone(bool ok) {
  Starts starts;
  {
    std::lock_guard lock(mutex_);
    writing_ = false;
    // !ok: the call is broken; the read side ends it and OnDone counts what is owed.
    if (ok) starts = next_starts_locked();
  }
  perform(starts);
}

void LoadStream::check_bricks() {
  for (const BrickBatchReader::Brick& brick : batch_.bricks()) {
    const auto payload =
        std::span(reinterpret_cast<const uint8_t*>(batch_.payloads().data()) + brick.payload_offset,
                  brick.payload_size);
    bool good =
        payload.size() >= kBrickHeaderSize && encoded_brick_checksum(payload) == brick.checksum;
    if (good) {
      try {
        (void)decode_brick(payload);
      } catch (const CodecError&) {
        good = false;
      }
    }
    if (!good) recorder_.checksum_failure();
  }
}

void LoadStream::answer_locked(const BrickKey& key, Clock::time_point now, std::size_t bytes,
                               int error_code) {
  const auto it = outstanding_.find(key);
  if (it == outstanding_.end()) {
    recorder_.unexpected();
    return;
  }
  if (error_code == 0) {
    recorder_.brick(it->second, now, bytes);
  } else {
    recorder_.brick_error(it->second, error_code);
  }
  outstanding_.erase(it);
  unpark_locked(key);
  if (settings_.in_flight > 0) issue_locked(now);  // closed loop: the next one goes now
}

void LoadStream::OnReadDone(bool ok) {
  if (!ok) {
    {
      std::lock_guard lock(mutex_);
      reads_ended_ = true;
    }
    perform({});
    return;
  }
  const Clock::time_point now = Clock::now();
  bool parsed;
  {
    grpc::ProtoBufferReader bytes(&read_);
    parsed = batch_.read(bytes, settings_.verify);
  }
  read_.Clear();
  if (!parsed) {
    // Not a BrickBatch: the typed API would have failed the call; end it, counted.
    recorder_.unexpected();
    context_.TryCancel();
    StartRead(&read_);  // completes not ok, which ends the reads
    return;
  }
  if (settings_.verify) check_bricks();  // outside the lock: decoding is the slow part
  Starts starts;
  {
    std::lock_guard lock(mutex_);
    for (const BrickBatchReader::Brick& brick : batch_.bricks()) {
      answer_locked(brick.key, now, brick.payload_size, 0);
    }
    for (const BrickBatchReader::Error& error : batch_.errors()) {
      // A per-brick error never has code OK; count a malformed one as UNKNOWN.
      answer_locked(error.key, now, 0, error.code == 0 ? 2 : error.code);
    }
    for (const int32_t code : batch_.request_errors()) recorder_.request_error(code);
    starts = next_starts_locked();
  }
  StartRead(&read_);
  perform(starts);
}

void LoadStream::OnDone(const grpc::Status& status) {
  {
    std::lock_guard lock(mutex_);
    recorder_.unanswered(outstanding_.size() + backlog_.size() + parked_count_);
    outstanding_.clear();
    backlog_.clear();
    parked_.clear();
    parked_count_ = 0;
    if (status.error_code() == grpc::StatusCode::CANCELLED && cancelled_here_.load()) {
      recorder_.stream_let_go();
    } else {
      recorder_.stream_ended(static_cast<int>(status.error_code()));
    }
    done_ = true;
  }
  on_done_();  // may destroy this stream: the last thing done here
}

}  // namespace soltex::load
