#include "server_metrics.h"

#include <array>
#include <optional>

#include "process_metrics.h"
#include "soltex/common/evaluation_counters.h"

namespace soltex::server {
namespace {

// Every family soltexd exposes: identifier, name, type, help. HELP and TYPE lines are made
// from this table only.
#define SOLTEX_METRIC_FAMILIES(X)                                                                 \
  X(build_info, "soltex_build_info", gauge, "Always 1; the version label is soltexd's version.")  \
  X(process_cpu, "process_cpu_seconds_total", counter, "User and system CPU time, seconds.")      \
  X(process_resident, "process_resident_memory_bytes", gauge, "Resident memory size, bytes.")     \
  X(process_virtual, "process_virtual_memory_bytes", gauge, "Virtual memory size, bytes.")        \
  X(process_open_fds, "process_open_fds", gauge, "Open file descriptors.")                        \
  X(process_max_fds, "process_max_fds", gauge, "The limit on open file descriptors.")             \
  X(process_start, "process_start_time_seconds", gauge,                                           \
    "Start time of the process since the Unix epoch, seconds.")                                   \
  X(grpc_started, "grpc_server_started_total", counter,                                           \
    "gRPC calls started on the server, every service.")                                           \
  X(grpc_handled, "grpc_server_handled_total", counter,                                           \
    "gRPC calls finished, by status code. A call gRPC ended before its status was sent "          \
    "(client cancel, deadline, a message over --max-message-bytes) counts as CANCELLED.")         \
  X(grpc_received, "grpc_server_msg_received_total", counter,                                     \
    "Messages received from clients, per method.")                                                \
  X(grpc_sent, "grpc_server_msg_sent_total", counter, "Messages sent to clients, per method.")    \
  X(grpc_cut_short, "soltex_grpc_calls_cut_short_total", counter,                                 \
    "Calls gRPC ended before the server's status was sent: the client cancelled or left, its "    \
    "deadline passed, or gRPC refused a message over --max-message-bytes (the client sees "       \
    "RESOURCE_EXHAUSTED).")                                                                       \
  X(streams_opened, "soltex_streams_opened_total", counter, "StreamBricks calls started.")        \
  X(streams_open, "soltex_streams_open", gauge, "StreamBricks calls in progress.")                \
  X(stream_messages, "soltex_stream_messages_total", counter, "BrickRequest messages read.")      \
  X(stream_messages_on_turns, "soltex_stream_messages_on_turns_total", counter,                   \
    "BrickRequest messages handled on a brick worker's turn, charged to their client, because "   \
    "gRPC's threads had spent their --direct-request-share.")                                     \
  X(register_requests, "soltex_register_requests_total", counter,                                 \
    "Texture registrations: RegisterTexture calls and textures carried on streams.")              \
  X(bricks_requested, "soltex_bricks_requested_total", counter,                                   \
    "Brick keys accepted into stream queues.")                                                    \
  X(bricks_served, "soltex_bricks_served_total", counter, "Bricks sent to clients.")              \
  X(bytes_served, "soltex_brick_bytes_served_total", counter,                                     \
    "Encoded brick bytes sent to clients.")                                                       \
  X(bricks_evaluated, "soltex_bricks_evaluated_total", counter,                                   \
    "Bricks evaluated from the texture function.")                                                \
  X(bricks_cancelled, "soltex_bricks_cancelled_total", counter,                                   \
    "Requested bricks never sent: cancelled by the client, or left when a stream was "            \
    "cancelled, closed or shut down.")                                                            \
  X(bricks_shared, "soltex_bricks_from_shared_cache_total", counter,                              \
    "Bricks another replica evaluated, read from the shared memcached cache.")                    \
  X(octaves_evaluated, "soltex_octave_samples_evaluated_total", counter,                          \
    "Noise octaves evaluated, times the samples they were evaluated at.")                         \
  X(octaves_skipped, "soltex_octave_samples_skipped_total", counter,                              \
    "Noise octaves a level could not show, replaced by their mean, times the samples.")           \
  X(queue_depth, "soltex_queue_depth", gauge, "Bricks queued over all streams.")                  \
  X(textures, "soltex_textures_registered", gauge, "Textures in the registry.")                   \
  X(textures_pinned, "soltex_textures_pinned", gauge,                                             \
    "Textures in the registry that an open stream uses (never evicted).")                         \
  X(registry_bytes, "soltex_texture_registry_bytes", gauge,                                       \
    "Memory charged to the registry's textures, bytes.")                                          \
  X(registry_budget, "soltex_texture_registry_budget_bytes", gauge,                               \
    "The registry's memory bound (--registry-mb), bytes.")                                        \
  X(textures_evicted, "soltex_textures_evicted_total", counter,                                   \
    "Textures evicted from the registry (least recently used, used by no open stream).")          \
  X(registrations_refused, "soltex_texture_registrations_refused_total", counter,                 \
    "Texture registrations refused: registry_full (every texture in use by a stream) or "         \
    "client_quota (the client's --max-textures-per-client all in use).")                          \
  X(cache_hits, "soltex_cache_hits_total", counter, "Brick cache hits.")                          \
  X(cache_misses, "soltex_cache_misses_total", counter, "Brick cache misses.")                    \
  X(cache_coalesced, "soltex_cache_coalesced_total", counter,                                     \
    "Cache misses that waited for a brick already being evaluated (single flight).")              \
  X(cache_evictions, "soltex_cache_evictions_total", counter, "Bricks evicted from the cache.")   \
  X(cache_bytes, "soltex_cache_bytes", gauge, "Bytes held by the brick cache.")                   \
  X(cache_budget, "soltex_cache_budget_bytes", gauge, "Byte budget of the brick cache.")          \
  X(cache_bricks, "soltex_cache_bricks", gauge, "Bricks held by the brick cache.")                \
  X(shared_hits, "soltex_shared_cache_hits_total", counter, "Shared (memcached) cache hits.")     \
  X(shared_misses, "soltex_shared_cache_misses_total", counter,                                   \
    "Shared (memcached) cache misses.")                                                           \
  X(shared_errors, "soltex_shared_cache_errors_total", counter,                                   \
    "Shared cache lookups that failed (node down or slow) and fell back to evaluation.")          \
  X(shared_corrupt, "soltex_shared_cache_corrupt_total", counter,                                 \
    "Shared cache values that failed their checksum and were evaluated instead.")                 \
  X(shared_stores, "soltex_shared_cache_stores_total", counter,                                   \
    "Bricks written back to the shared cache.")                                                   \
  X(shared_store_errors, "soltex_shared_cache_store_errors_total", counter,                       \
    "Write-backs to the shared cache that failed (ignored).")                                     \
  X(shared_skipped, "soltex_shared_cache_skipped_total", counter,                                 \
    "Shared cache lookups and write-backs not tried: their node rests after a timeout.")          \
  X(faults_corrupted, "soltex_faults_corrupted_total", counter,                                   \
    "Bricks deliberately corrupted on the way out (--fault-corrupt-every).")                      \
  X(reloads, "soltex_config_reloads_total", counter,                                              \
    "SIGHUP reloads of the TLS files and the tokens file, by result (ok, failed).")               \
  X(refusal_lines_suppressed, "soltex_refusal_log_lines_suppressed_total", counter,               \
    "Warnings about refused calls left out of the log (at most one a second per client).")        \
  X(errors, "soltex_errors_total", counter,                                                       \
    "Per-brick and per-request errors the handlers answered, by gRPC status code.")               \
  X(brick_latency, "soltex_brick_latency_seconds", histogram,                                     \
    "From a brick entering a stream's queue to its batch being written.")                         \
  X(brick_stages, "soltex_brick_stage_seconds", histogram,                                        \
    "Time per brick in each stage: queue_wait (queued until a worker takes it), evaluate, "       \
    "encode (quantize, predictor, compression, checksum), outbox_wait (made or found in the "     \
    "cache until its message goes to gRPC); write is per message, from gRPC taking it to "        \
    "gRPC reporting it written.")                                                                 \
  X(http_responses, "soltex_http_responses_total", counter,                                       \
    "HTTP responses (--http-listen), by route and status code (\"other\": any code not listed).") \
  X(http_connections, "soltex_http_connections_total", counter, "HTTP connections accepted.")     \
  X(http_connections_open, "soltex_http_connections_open", gauge, "HTTP connections open.")       \
  X(http_refused, "soltex_http_connections_refused_total", counter,                               \
    "HTTP connections answered 503 and closed (over TLS, closed): --http-max-connections were "   \
    "open, or --http-max-connections-per-client from its client.")                                \
  X(http_timeouts, "soltex_http_timeouts_total", counter,                                         \
    "HTTP connections closed because a request or response took longer than --http-timeout-s.")   \
  X(http_bricks, "soltex_http_bricks_served_total", counter, "Bricks sent over HTTP (200s).")     \
  X(http_brick_bytes, "soltex_http_brick_bytes_served_total", counter,                            \
    "Encoded brick bytes sent over HTTP.")

enum class F : std::size_t {
#define SOLTEX_METRIC_ID(id, name, type, help) id,
  SOLTEX_METRIC_FAMILIES(SOLTEX_METRIC_ID)
#undef SOLTEX_METRIC_ID
};

constexpr MetricFamily kFamilies[] = {
#define SOLTEX_METRIC_ENTRY(id, name, type, help) {name, MetricType::type, help},
    SOLTEX_METRIC_FAMILIES(SOLTEX_METRIC_ENTRY)
#undef SOLTEX_METRIC_ENTRY
};

const MetricFamily& family(F id) {
  return kFamilies[static_cast<std::size_t>(id)];
}

// Writes one family with its single unlabelled sample.
void single(Exposition& e, F id, double value) {
  e.family(family(id));
  e.sample(value);
}

void write_process(Exposition& e) {
  e.family(family(F::build_info));
  e.sample(1.0, {{"version", SOLTEX_VERSION}});
  const std::optional<ProcessStats> p = read_process_stats();
  if (!p) return;
  single(e, F::process_cpu, p->cpu_seconds);
  single(e, F::process_resident, p->resident_bytes);
  single(e, F::process_virtual, p->virtual_bytes);
  single(e, F::process_open_fds, p->open_fds);
  single(e, F::process_max_fds, p->max_fds);
  single(e, F::process_start, p->start_time_seconds);
}

void write_brick_latency(Exposition& e, const LatencyHistogram& histogram) {
  // Fixed boundaries in seconds, filled from the log-linear histogram; up to 30 s, since a
  // brick queued behind a busy server's others waits seconds (docs/OPERATIONS.md).
  static constexpr double kBounds[] = {50e-6, 100e-6, 250e-6, 500e-6, 1e-3, 2.5e-3,
                                       5e-3,  10e-3,  25e-3,  50e-3,  0.1,  0.25,
                                       0.5,   1.0,    2.5,    5.0,    10.0, 30.0};
  const LatencyHistogramSnapshot snapshot = histogram.snapshot();
  std::array<uint64_t, std::size(kBounds)> cumulative{};
  for (std::size_t i = 0; i < cumulative.size(); ++i) {
    cumulative[i] = snapshot.cumulative_count_at_or_below(static_cast<uint64_t>(kBounds[i] * 1e9));
  }
  e.family(family(F::brick_latency));
  e.histogram(kBounds, cumulative, snapshot.count(),
              snapshot.mean() * static_cast<double>(snapshot.count()) * 1e-9);
}

void write_brick_stages(Exposition& e, std::span<const LatencyHistogram, kBrickStages> stages) {
  // Finer at the low end than the latency family: a stage of a cached brick takes microseconds.
  static constexpr double kBounds[] = {1e-6,   2.5e-6, 5e-6,   10e-6,  25e-6,  50e-6,
                                       100e-6, 250e-6, 500e-6, 1e-3,   2.5e-3, 5e-3,
                                       10e-3,  25e-3,  50e-3,  100e-3, 250e-3, 1.0};
  e.family(family(F::brick_stages));
  for (std::size_t s = 0; s < kBrickStages; ++s) {
    const LatencyHistogramSnapshot snapshot = stages[s].snapshot();
    std::array<uint64_t, std::size(kBounds)> cumulative{};
    for (std::size_t i = 0; i < cumulative.size(); ++i) {
      cumulative[i] =
          snapshot.cumulative_count_at_or_below(static_cast<uint64_t>(kBounds[i] * 1e9));
    }
    e.histogram(kBounds, cumulative, snapshot.count(),
                snapshot.mean() * static_cast<double>(snapshot.count()) * 1e-9,
                {{"stage", brick_stage_name(static_cast<BrickStage>(s))}});
  }
}

void write_shared_cache(Exposition& e, const SharedCacheStats& shared) {
  const auto counter = [&](F id, uint64_t value) { single(e, id, static_cast<double>(value)); };
  counter(F::shared_hits, shared.hits);
  counter(F::shared_misses, shared.misses);
  counter(F::shared_errors, shared.errors);
  counter(F::shared_corrupt, shared.corrupt);
  counter(F::shared_stores, shared.stores);
  counter(F::shared_store_errors, shared.store_errors);
  counter(F::shared_skipped, shared.skipped);
}

void write_registry(Exposition& e, const RegistryStats& registry) {
  const auto value = [&](F id, auto v) { single(e, id, static_cast<double>(v)); };
  value(F::textures, registry.textures);
  value(F::textures_pinned, registry.pinned);
  value(F::registry_bytes, registry.bytes);
  value(F::registry_budget, registry.max_bytes);
  value(F::textures_evicted, registry.evicted);
  e.family(family(F::registrations_refused));
  e.sample(static_cast<double>(registry.refused_full), {{"reason", "registry_full"}});
  e.sample(static_cast<double>(registry.refused_client_quota), {{"reason", "client_quota"}});
}

void write_access(Exposition& e, const AccessCounts& access) {
  e.family(family(F::reloads));
  e.sample(static_cast<double>(access.reloads_ok), {{"result", "ok"}});
  e.sample(static_cast<double>(access.reloads_failed), {{"result", "failed"}});
  single(e, F::refusal_lines_suppressed, static_cast<double>(access.refusal_lines_suppressed));
}

void write_http(Exposition& e, const HttpMetrics& http) {
  const auto load = [](const auto& a) {
    return static_cast<double>(a.load(std::memory_order_relaxed));
  };
  e.family(family(F::http_responses));
  for (std::size_t route = 0; route < http.responses.size(); ++route) {
    for (std::size_t slot = 0; slot <= HttpMetrics::kKnownStatuses; ++slot) {
      const std::string code = slot < HttpMetrics::kKnownStatuses
                                   ? std::to_string(HttpMetrics::kStatuses[slot])
                                   : std::string("other");
      e.sample(load(http.responses[route][slot]),
               {{"route", HttpMetrics::route_name(route)}, {"code", code}});
    }
  }
  single(e, F::http_connections, load(http.connections_opened));
  single(e, F::http_connections_open, load(http.connections_open));
  single(e, F::http_refused, load(http.connections_refused));
  single(e, F::http_timeouts, load(http.timeouts));
  single(e, F::http_bricks, load(http.bricks_served));
  single(e, F::http_brick_bytes, load(http.brick_bytes));
}

}  // namespace

const char* brick_stage_name(BrickStage stage) {
  switch (stage) {
    case BrickStage::queue_wait:
      return "queue_wait";
    case BrickStage::evaluate:
      return "evaluate";
    case BrickStage::encode:
      return "encode";
    case BrickStage::outbox_wait:
      return "outbox_wait";
    case BrickStage::write:
      return "write";
  }
  return "unknown";
}

std::span<const MetricFamily> metric_families() {
  return kFamilies;
}

std::string ServerMetrics::render(const BrickStoreStats& store, std::size_t store_budget,
                                  const RegistryStats& registry, const SharedCacheStats* shared,
                                  uint64_t faults_corrupted, const AccessCounts& access) const {
  Exposition e;
  const auto value = [&](F id, auto v) { single(e, id, static_cast<double>(v)); };
  const auto load = [](const auto& a) { return a.load(std::memory_order_relaxed); };

  write_process(e);
  grpc_calls.write(e, {family(F::grpc_started), family(F::grpc_handled), family(F::grpc_received),
                       family(F::grpc_sent), family(F::grpc_cut_short)});
  value(F::streams_opened, load(streams_opened));
  value(F::streams_open, load(streams_open));
  value(F::stream_messages, load(stream_messages));
  value(F::stream_messages_on_turns, load(stream_messages_on_turns));
  value(F::register_requests, load(register_requests));
  value(F::bricks_requested, load(bricks_requested));
  value(F::bricks_served, load(bricks_served));
  value(F::bytes_served, load(bytes_served));
  value(F::bricks_evaluated, load(bricks_evaluated));
  value(F::bricks_cancelled, load(bricks_cancelled));
  value(F::bricks_shared, load(bricks_from_shared_cache));
  const OctaveCounts octaves = octave_counters().snapshot();
  value(F::octaves_evaluated, octaves.evaluated_octave_samples);
  value(F::octaves_skipped, octaves.skipped_octave_samples);
  value(F::queue_depth, load(queue_depth));
  write_registry(e, registry);
  value(F::cache_hits, store.hits);
  value(F::cache_misses, store.misses);
  value(F::cache_coalesced, store.coalesced);
  value(F::cache_evictions, store.evictions);
  value(F::cache_bytes, store.bytes);
  value(F::cache_budget, store_budget);
  value(F::cache_bricks, store.entries);
  if (shared) write_shared_cache(e, *shared);
  value(F::faults_corrupted, faults_corrupted);
  write_access(e, access);

  // gRPC's label name for a status code, as the grpc_server_* families use it.
  e.family(family(F::errors));
  for (std::size_t code = 1; code < errors_by_code.size(); ++code) {
    e.sample(static_cast<double>(load(errors_by_code[code])),
             {{"grpc_code", grpc_code_name(static_cast<int>(code))}});
  }
  write_brick_latency(e, brick_latency_ns);
  write_brick_stages(e, stage_ns);
  write_http(e, http);
  return e.take();
}

}  // namespace soltex::server
