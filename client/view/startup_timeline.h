#pragma once

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "soltex/net/brick_fetcher.h"

namespace soltex::view {

// What happened when, from the program's start to the converged frame, for finding idle gaps
// and serial waits in a cold start (soltex-view --timeline). Any thread may mark; marks are
// kept in the order they were made, each with its time since `origin`.
class StartupTimeline {
 public:
  using Clock = std::chrono::steady_clock;

  explicit StartupTimeline(Clock::time_point origin = Clock::now());

  void mark(std::string what);
  // Milliseconds since the origin.
  double now_ms() const;
  // One line per mark: milliseconds since the origin, since the mark before, the process's
  // CPU time since the origin's moment in the mark before, and what; first, the origin on the
  // system's monotonic clock (CLOCK_MONOTONIC, seconds), to line marks up with other processes.
  void print(std::FILE* out) const;

 private:
  struct Mark {
    double ms;
    double cpu_ms;  // this process's CPU time (all threads) at the mark
    std::string what;
  };
  const Clock::time_point origin_;
  double origin_cpu_ms_;
  mutable std::mutex mutex_;
  std::vector<Mark> marks_;
};

// `timeline`'s mark, where there is a timeline (null: nothing is being timed).
inline void mark_on(StartupTimeline* timeline, std::string what) {
  if (timeline != nullptr) timeline->mark(std::move(what));
}

// A BrickFetcher's events (FetcherOptions::on_event) as marks on `timeline`: the stream
// opening, each request written, each batch received with the count so far.
std::function<void(net::FetchEvent, std::size_t)> fetch_marks(StartupTimeline& timeline);

}  // namespace soltex::view
