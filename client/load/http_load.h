#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "load_options.h"

// soltex-load --http: the HTTP brick path (docs/PROTOCOL.md section 9) under load, through
// soltexd's --http-listen or a caching proxy in front of it. Each connection is one keep-alive
// HTTP/1.1 connection on its own thread asking for one brick at a time (closed loop), keys
// from the same mixes as the gRPC runs.
namespace soltex::load {

struct HttpLoadResult {
  double seconds = 0.0;  // measured, after the warmup
  int connections = 0;
  uint64_t requests = 0;
  uint64_t bricks = 0;  // 200s with a brick
  uint64_t bytes = 0;
  double bricks_per_second = 0.0;
  // Latency of a request, from writing it to reading its whole answer, microseconds.
  double p50_us = 0, p90_us = 0, p99_us = 0, max_us = 0;
  std::map<int, uint64_t> statuses;                // HTTP status -> responses
  std::map<std::string, uint64_t> cache_statuses;  // X-Cache-Status value ("none": absent)
  uint64_t checksum_failures = 0;                  // --verify
  uint64_t connection_errors = 0;                  // reconnects after a failed exchange
  std::string texture_id;
};

// Registers the run's texture with POST /v1/textures (through the target, like the bricks),
// then loads. Throws LoadSetupError when the target does not answer or refuses the texture.
HttpLoadResult run_http_load(const LoadOptions& options);

std::string format_http_result(const HttpLoadResult& result, OutputFormat format);

}  // namespace soltex::load
