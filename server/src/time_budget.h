#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>

namespace soltex::server {

// A share of one thread's time, kept as a token bucket: work may start while there is credit,
// what it took is spent afterwards (so credit may go below zero), and credit comes back at
// `share` seconds per second of wall time, up to `burst`. A share of 0 never has credit.
// Thread-safe.
class TimeBudget {
 public:
  using Clock = std::chrono::steady_clock;

  TimeBudget(double share, std::chrono::nanoseconds burst);

  bool has_credit(Clock::time_point now = Clock::now());
  void spend(std::chrono::nanoseconds used);

 private:
  void refill(Clock::time_point now);  // mutex_ held

  const double share_;
  const int64_t burst_ns_;
  std::mutex mutex_;
  int64_t credit_ns_;
  Clock::time_point refilled_;
};

}  // namespace soltex::server
