#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>

#include "load_result.h"
#include "request_mix.h"
#include "soltex/common/latency_histogram.h"

namespace soltex::load {

using Clock = std::chrono::steady_clock;

// What the streams observe, recorded lock-free from gRPC's threads; read by the progress line
// while the run goes on and turned into a LoadResult at the end.
class LoadRecorder {
 public:
  struct Progress {
    uint64_t bricks = 0;  // whole run
    uint64_t errors = 0;  // per-brick, request and stream errors, whole run
  };

  // Requests intended at or after `measure_from` are measured; earlier ones are the warmup.
  explicit LoadRecorder(Clock::time_point measure_from) : measure_from_(measure_from) {}

  bool measured(Clock::time_point intended) const { return intended >= measure_from_; }

  void requested(bool measured, InvalidKind invalid);
  void brick(Clock::time_point intended, Clock::time_point answered, std::size_t bytes);
  void brick_error(Clock::time_point intended, int code);
  void request_error(int code);
  void stream_ended(int code);
  // A stream this tool cancelled at the drain timeout (LoadResult::streams_let_go).
  void stream_let_go() { add(streams_let_go_, 1); }
  void unanswered(uint64_t n) { add(unanswered_, n); }
  void dropped_backlog() { add(dropped_backlog_, 1); }
  void unexpected() { add(unexpected_, 1); }
  void checksum_failure() { add(checksum_failures_, 1); }

  Progress progress() const;

  // Fills the counters and latency of `result`. The measured window runs from measure_from
  // to the last measured answer, but not shorter than to `window_end` (a duration run whose
  // last request went out before the stop time still offered load until then).
  void fill(LoadResult& result, Clock::time_point window_end) const;

 private:
  using Counter = std::atomic<uint64_t>;
  static void add(Counter& c, uint64_t n) { c.fetch_add(n, std::memory_order_relaxed); }
  static void add_code(std::array<Counter, 17>& counts, int code);
  static CodeCounts load(const std::array<Counter, 17>& counts);

  const Clock::time_point measure_from_;
  LatencyHistogram latency_;
  Counter requests_{0}, total_requests_{0};
  Counter bricks_{0}, total_bricks_{0};
  Counter bytes_{0}, total_bytes_{0};
  std::array<Counter, 17> brick_errors_{}, total_brick_errors_{}, request_errors_{},
      stream_status_{};
  Counter unanswered_{0}, dropped_backlog_{0}, unexpected_{0}, checksum_failures_{0},
      streams_let_go_{0};
  Counter injected_out_of_range_{0}, injected_unknown_texture_{0};
  std::atomic<int64_t> last_measured_answer_ns_{0};  // since measure_from_
};

}  // namespace soltex::load
