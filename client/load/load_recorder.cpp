#include "load_recorder.h"

#include <algorithm>

namespace soltex::load {

void LoadRecorder::add_code(std::array<Counter, 17>& counts, int code) {
  // Codes beyond the known ones are counted as UNKNOWN rather than lost.
  const std::size_t index = code >= 0 && code < 17 ? static_cast<std::size_t>(code) : 2;
  add(counts[index], 1);
}

CodeCounts LoadRecorder::load(const std::array<Counter, 17>& counts) {
  CodeCounts result{};
  for (std::size_t i = 0; i < counts.size(); ++i) {
    result[i] = counts[i].load(std::memory_order_relaxed);
  }
  return result;
}

void LoadRecorder::requested(bool measured, InvalidKind invalid) {
  add(total_requests_, 1);
  if (measured) add(requests_, 1);
  if (invalid == InvalidKind::out_of_range) add(injected_out_of_range_, 1);
  if (invalid == InvalidKind::unknown_texture) add(injected_unknown_texture_, 1);
}

void LoadRecorder::brick(Clock::time_point intended, Clock::time_point answered,
                         std::size_t bytes) {
  add(total_bricks_, 1);
  add(total_bytes_, bytes);
  if (!measured(intended)) return;
  add(bricks_, 1);
  add(bytes_, bytes);
  latency_.record(static_cast<uint64_t>(std::max<int64_t>(
      0, std::chrono::duration_cast<std::chrono::nanoseconds>(answered - intended).count())));
  const int64_t since =
      std::chrono::duration_cast<std::chrono::nanoseconds>(answered - measure_from_).count();
  int64_t last = last_measured_answer_ns_.load(std::memory_order_relaxed);
  while (since > last &&
         !last_measured_answer_ns_.compare_exchange_weak(last, since, std::memory_order_relaxed)) {
  }
}

void LoadRecorder::brick_error(Clock::time_point intended, int code) {
  add_code(total_brick_errors_, code);
  if (measured(intended)) add_code(brick_errors_, code);
}

void LoadRecorder::request_error(int code) {
  add_code(request_errors_, code);
}

void LoadRecorder::stream_ended(int code) {
  add_code(stream_status_, code);
}

LoadRecorder::Progress LoadRecorder::progress() const {
  Progress p;
  p.bricks = total_bricks_.load(std::memory_order_relaxed);
  for (const auto* counts : {&total_brick_errors_, &request_errors_}) {
    for (const Counter& c : *counts) p.errors += c.load(std::memory_order_relaxed);
  }
  for (std::size_t code = 1; code < stream_status_.size(); ++code) {
    p.errors += stream_status_[code].load(std::memory_order_relaxed);
  }
  return p;
}

void LoadRecorder::fill(LoadResult& r, Clock::time_point window_end) const {
  const auto relaxed = std::memory_order_relaxed;
  r.requests = requests_.load(relaxed);
  r.bricks = bricks_.load(relaxed);
  r.bytes = bytes_.load(relaxed);
  r.brick_errors = load(brick_errors_);
  r.latency = LatencySummary::of(latency_.snapshot());
  r.total_requests = total_requests_.load(relaxed);
  r.total_bricks = total_bricks_.load(relaxed);
  r.total_bytes = total_bytes_.load(relaxed);
  r.total_brick_errors = load(total_brick_errors_);
  r.request_errors = load(request_errors_);
  r.stream_status = load(stream_status_);
  r.unanswered = unanswered_.load(relaxed);
  r.streams_let_go = streams_let_go_.load(relaxed);
  r.dropped_backlog = dropped_backlog_.load(relaxed);
  r.unexpected = unexpected_.load(relaxed);
  r.checksum_failures = checksum_failures_.load(relaxed);
  r.injected_out_of_range = injected_out_of_range_.load(relaxed);
  r.injected_unknown_texture = injected_unknown_texture_.load(relaxed);
  const double last = static_cast<double>(last_measured_answer_ns_.load(relaxed)) * 1e-9;
  r.measured_seconds =
      std::max({0.0, last, std::chrono::duration<double>(window_end - measure_from_).count()});
}

}  // namespace soltex::load
