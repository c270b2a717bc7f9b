#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string_view>

namespace soltex::server {

// The HTTP brick endpoint's counters (rendered by ServerMetrics with the rest).
struct HttpMetrics {
  enum class Route : std::size_t { register_texture, texture, brick, preflight, other, count };
  // The statuses the endpoint answers with; anything else counts as "other".
  static constexpr std::array<unsigned, 16> kStatuses = {200, 204, 304, 400, 401, 404, 405, 408,
                                                         412, 413, 414, 429, 431, 500, 501, 503};
  static constexpr std::size_t kKnownStatuses = kStatuses.size();

  std::array<std::array<std::atomic<uint64_t>, kKnownStatuses + 1>,
             static_cast<std::size_t>(Route::count)>
      responses{};
  std::atomic<uint64_t> connections_opened{0};
  std::atomic<int64_t> connections_open{0};
  std::atomic<uint64_t> connections_refused{0};  // over --http-max-connections
  std::atomic<uint64_t> timeouts{0};             // a request not read or written in time
  std::atomic<uint64_t> bricks_served{0};        // 200s with a brick body
  std::atomic<uint64_t> brick_bytes{0};

  void count(Route route, unsigned status) {
    std::size_t slot = kKnownStatuses;
    for (std::size_t i = 0; i < kKnownStatuses; ++i) {
      if (kStatuses[i] == status) slot = i;
    }
    responses[static_cast<std::size_t>(route)][slot].fetch_add(1, std::memory_order_relaxed);
  }

  static std::string_view route_name(std::size_t route) {
    static constexpr std::string_view kNames[] = {"register", "texture", "brick", "preflight",
                                                  "other"};
    return kNames[route];
  }
};

}  // namespace soltex::server
