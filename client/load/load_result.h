#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "load_options.h"
#include "soltex/common/latency_histogram.h"

namespace soltex::load {

// Counts per gRPC status code, 0 (OK) .. 16 (UNAUTHENTICATED).
using CodeCounts = std::array<uint64_t, 17>;

const char* status_code_name(int code);

// Per-brick latency of the measured bricks, nanoseconds.
struct LatencySummary {
  uint64_t count = 0;
  uint64_t min = 0;
  double mean = 0.0;
  uint64_t p50 = 0;
  uint64_t p90 = 0;
  uint64_t p99 = 0;
  uint64_t p999 = 0;
  uint64_t max = 0;
  std::vector<HistogramBucket> buckets;  // the histogram's non-empty buckets

  static LatencySummary of(const LatencyHistogramSnapshot& snapshot);
};

// What a run did. "Measured" is everything asked for after the warmup; totals include it.
struct LoadResult {
  LoadOptions options;  // resolved
  uint64_t texture_id = 0;
  int texture_levels = 0;
  int server_workers = 0;

  double elapsed_seconds = 0.0;   // start of the load to the last stream's end (or stop time)
  double measured_seconds = 0.0;  // end of the warmup to the last measured answer

  // Measured.
  uint64_t requests = 0;  // brick requests made (including ones dropped or unanswered)
  uint64_t bricks = 0;
  uint64_t bytes = 0;  // encoded brick payload bytes
  CodeCounts brick_errors{};
  LatencySummary latency;

  // Whole run.
  uint64_t total_requests = 0;
  uint64_t total_bricks = 0;
  uint64_t total_bytes = 0;
  CodeCounts total_brick_errors{};
  CodeCounts request_errors{};     // BrickBatch.request_errors
  CodeCounts stream_status{};      // how each stream ended (OK counts clean ends)
  uint64_t unanswered = 0;         // sent or queued, no answer by the end (drain timeout, failure)
  uint64_t streams_let_go = 0;     // cancelled here at --drain-timeout-s: no failure, not OK
  uint64_t dropped_backlog = 0;    // not sent: the stream's unsent backlog was full
  uint64_t unexpected = 0;         // answers for keys the stream was not waiting for
  uint64_t checksum_failures = 0;  // with --verify: bricks that did not decode to their checksum
  uint64_t injected_out_of_range = 0;
  uint64_t injected_unknown_texture = 0;
  // Open loop: how far behind its schedule the sender fell at worst. Large values mean the
  // client, not the server, limited the offered load.
  double max_send_lag_seconds = 0.0;

  double bricks_per_second() const;
  double megabytes_per_second() const;  // 10^6 bytes
  uint64_t measured_errors() const;     // per-brick errors of measured requests
  uint64_t stream_failures() const;     // streams that ended with a status other than OK
};

}  // namespace soltex::load
