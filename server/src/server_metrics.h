#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <span>
#include <string>

#include "brick_store.h"
#include "grpc_call_metrics.h"
#include "http_metrics.h"
#include "metrics_exposition.h"
#include "shared_brick_cache.h"
#include "soltex/common/latency_histogram.h"
#include "texture_registry.h"

namespace soltex::server {

// Where a brick's time goes inside soltexd, stage by stage (soltex_brick_stage_seconds).
enum class BrickStage : std::size_t {
  queue_wait,   // from entering its stream's queue to a worker starting to make it
  evaluate,     // evaluating the texture function over the brick's samples
  encode,       // quantizing, the predictor, zstd or lz4, and the checksum
  outbox_wait,  // from made (or found in the cache) to its message being handed to gRPC
  write,        // per message: from handing it to gRPC to gRPC reporting it written
};
inline constexpr std::size_t kBrickStages = 5;
const char* brick_stage_name(BrickStage stage);

// Counted outside ServerMetrics: SIGHUP reloads and refusal log lines left out.
struct AccessCounts {
  uint64_t reloads_ok = 0;
  uint64_t reloads_failed = 0;
  uint64_t refusal_lines_suppressed = 0;
};

// The daemon's counters, updated lock-free from any thread and rendered in the Prometheus
// text exposition format for GET /metrics. Every family it renders is in one table
// (metric_families()).
struct ServerMetrics {
  std::atomic<uint64_t> streams_opened{0};
  std::atomic<int64_t> streams_open{0};
  std::atomic<uint64_t> stream_messages{0};           // BrickRequest messages read
  std::atomic<uint64_t> stream_messages_on_turns{0};  // of those, handled on a worker's turn
  std::atomic<uint64_t> register_requests{0};
  std::atomic<uint64_t> bricks_requested{0};  // wanted keys accepted into a queue
  std::atomic<uint64_t> bricks_served{0};
  std::atomic<uint64_t> bytes_served{0};  // brick payload bytes
  std::atomic<uint64_t> bricks_evaluated{0};
  std::atomic<uint64_t> bricks_from_shared_cache{0};       // made by another replica
  std::atomic<uint64_t> bricks_cancelled{0};               // requested, then dropped unserved
  std::atomic<int64_t> queue_depth{0};                     // bricks queued over all streams
  std::array<std::atomic<uint64_t>, 17> errors_by_code{};  // grpc::StatusCode 0..16
  // From a brick entering a stream's queue to its batch being handed to gRPC, nanoseconds.
  LatencyHistogram brick_latency_ns;
  std::array<LatencyHistogram, kBrickStages> stage_ns;  // by BrickStage, nanoseconds
  GrpcCallMetrics grpc_calls;  // every call, by method and status, from a server interceptor
  HttpMetrics http;            // the HTTP brick endpoint (--http-listen)

  void record(BrickStage stage, std::chrono::steady_clock::duration elapsed) {
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(elapsed).count();
    stage_ns[static_cast<std::size_t>(stage)].record(static_cast<uint64_t>(ns > 0 ? ns : 0));
  }

  void count_error(int code) {
    if (code >= 0 && code < static_cast<int>(errors_by_code.size())) {
      errors_by_code[static_cast<std::size_t>(code)].fetch_add(1, std::memory_order_relaxed);
    }
  }

  // `shared` is null when no shared cache is configured.
  std::string render(const BrickStoreStats& store, std::size_t store_budget,
                     const RegistryStats& registry, const SharedCacheStats* shared,
                     uint64_t faults_corrupted, const AccessCounts& access) const;
};

// Every family /metrics may show (some only with a shared cache configured), in page order.
std::span<const MetricFamily> metric_families();

}  // namespace soltex::server
