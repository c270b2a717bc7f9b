#include "server_metrics.h"

#include <cstdio>

#include "soltex/common/evaluation_counters.h"

namespace soltex::server {
namespace {

const char* const kCodeNames[17] = {
    "OK",        "CANCELLED",      "UNKNOWN",           "INVALID_ARGUMENT",   "DEADLINE_EXCEEDED",
    "NOT_FOUND", "ALREADY_EXISTS", "PERMISSION_DENIED", "RESOURCE_EXHAUSTED", "FAILED_PRECONDITION",
    "ABORTED",   "OUT_OF_RANGE",   "UNIMPLEMENTED",     "INTERNAL",           "UNAVAILABLE",
    "DATA_LOSS", "UNAUTHENTICATED"};

class Exposition {
 public:
  void metric(const char* name, const char* type, const char* help) {
    out_ += "# HELP ";
    out_ += name;
    out_ += ' ';
    out_ += help;
    out_ += "\n# TYPE ";
    out_ += name;
    out_ += ' ';
    out_ += type;
    out_ += '\n';
  }
  void sample(const std::string& name, double value) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, " %.17g\n", value);
    out_ += name;
    out_ += buffer;
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

}  // namespace

std::string ServerMetrics::render(const BrickStoreStats& store, std::size_t store_budget,
                                  std::size_t textures, const SharedCacheStats* shared,
                                  uint64_t faults_corrupted) const {
  Exposition e;
  const auto counter = [&](const char* name, const char* help, uint64_t value) {
    e.metric(name, "counter", help);
    e.sample(name, static_cast<double>(value));
  };
  const auto gauge = [&](const char* name, const char* help, double value) {
    e.metric(name, "gauge", help);
    e.sample(name, value);
  };
  const auto load = [](const auto& a) { return a.load(std::memory_order_relaxed); };

  counter("soltex_streams_opened_total", "StreamBricks calls started.", load(streams_opened));
  gauge("soltex_streams_open", "StreamBricks calls in progress.",
        static_cast<double>(load(streams_open)));
  counter("soltex_stream_messages_total", "BrickRequest messages read.", load(stream_messages));
  counter("soltex_register_requests_total", "RegisterTexture calls.", load(register_requests));
  counter("soltex_bricks_requested_total", "Brick keys accepted into stream queues.",
          load(bricks_requested));
  counter("soltex_bricks_served_total", "Bricks sent to clients.", load(bricks_served));
  counter("soltex_brick_bytes_served_total", "Encoded brick bytes sent to clients.",
          load(bytes_served));
  counter("soltex_bricks_evaluated_total", "Bricks evaluated from the texture function.",
          load(bricks_evaluated));
  counter("soltex_bricks_cancelled_total", "Queued bricks dropped by client cancellations.",
          load(bricks_cancelled));
  counter("soltex_bricks_from_shared_cache_total",
          "Bricks another replica evaluated, read from the shared memcached cache.",
          load(bricks_from_shared_cache));
  const OctaveCounts octaves = octave_counters().snapshot();
  counter("soltex_octave_samples_evaluated_total",
          "Noise octaves evaluated, times the samples they were evaluated at.",
          octaves.evaluated_octave_samples);
  counter("soltex_octave_samples_skipped_total",
          "Noise octaves a level could not show, replaced by their mean, times the samples.",
          octaves.skipped_octave_samples);
  gauge("soltex_queue_depth", "Bricks queued over all streams.",
        static_cast<double>(load(queue_depth)));
  gauge("soltex_textures_registered", "Textures in the registry.", static_cast<double>(textures));
  counter("soltex_cache_hits_total", "Brick cache hits.", store.hits);
  counter("soltex_cache_misses_total", "Brick cache misses.", store.misses);
  counter("soltex_cache_coalesced_total",
          "Cache misses that waited for a brick already being evaluated (single flight).",
          store.coalesced);
  counter("soltex_cache_evictions_total", "Bricks evicted from the cache.", store.evictions);
  gauge("soltex_cache_bytes", "Bytes held by the brick cache.", static_cast<double>(store.bytes));
  gauge("soltex_cache_budget_bytes", "Byte budget of the brick cache.",
        static_cast<double>(store_budget));
  gauge("soltex_cache_bricks", "Bricks held by the brick cache.",
        static_cast<double>(store.entries));

  if (shared) {
    counter("soltex_shared_cache_hits_total", "Shared (memcached) cache hits.", shared->hits);
    counter("soltex_shared_cache_misses_total", "Shared (memcached) cache misses.", shared->misses);
    counter("soltex_shared_cache_errors_total",
            "Shared cache lookups that failed (node down or slow) and fell back to evaluation.",
            shared->errors);
    counter("soltex_shared_cache_corrupt_total",
            "Shared cache values that failed their checksum and were evaluated instead.",
            shared->corrupt);
    counter("soltex_shared_cache_stores_total", "Bricks written back to the shared cache.",
            shared->stores);
    counter("soltex_shared_cache_store_errors_total",
            "Write-backs to the shared cache that failed (ignored).", shared->store_errors);
  }
  counter("soltex_faults_corrupted_total",
          "Bricks deliberately corrupted on the way out (--fault-corrupt-every).",
          faults_corrupted);

  e.metric("soltex_errors_total", "Per-brick and per-request errors by gRPC status code.",
           "counter");
  for (std::size_t code = 1; code < errors_by_code.size(); ++code) {
    e.sample(std::string("soltex_errors_total{code=\"") + kCodeNames[code] + "\"}",
             static_cast<double>(load(errors_by_code[code])));
  }

  // Fixed boundaries in seconds, filled from the log-linear histogram.
  e.metric("soltex_brick_latency_seconds",
           "From a brick entering a stream's queue to its batch being written.", "histogram");
  const LatencyHistogramSnapshot snapshot = brick_latency_ns.snapshot();
  static constexpr double kBounds[] = {50e-6, 100e-6, 250e-6, 500e-6, 1e-3,   2.5e-3, 5e-3, 10e-3,
                                       25e-3, 50e-3,  100e-3, 250e-3, 500e-3, 1.0,    2.5};
  for (double bound : kBounds) {
    char label[64];
    std::snprintf(label, sizeof label, "{le=\"%g\"}", bound);
    e.sample(std::string("soltex_brick_latency_seconds_bucket") + label,
             static_cast<double>(
                 snapshot.cumulative_count_at_or_below(static_cast<uint64_t>(bound * 1e9))));
  }
  e.sample("soltex_brick_latency_seconds_bucket{le=\"+Inf\"}",
           static_cast<double>(snapshot.count()));
  e.sample("soltex_brick_latency_seconds_sum",
           snapshot.mean() * static_cast<double>(snapshot.count()) * 1e-9);
  e.sample("soltex_brick_latency_seconds_count", static_cast<double>(snapshot.count()));
  return e.take();
}

}  // namespace soltex::server
