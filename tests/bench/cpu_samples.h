#pragma once

#include <time.h>

#include <algorithm>
#include <cstddef>
#include <vector>

// For benchmarks that time their frames one by one (to pair them, or to split a frame's
// parts): a CPU clock read directly, and the median of the samples taken.

// CPU time of `clock` (CLOCK_THREAD_CPUTIME_ID: the calling thread; CLOCK_PROCESS_CPUTIME_ID:
// every thread of the process), in nanoseconds.
inline double cpu_clock_ns(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) * 1e9 + static_cast<double>(t.tv_nsec);
}

// The median of `samples` (the upper one of an even count); 0 when there are none.
inline double median(std::vector<double> samples) {
  if (samples.empty()) return 0.0;
  const auto middle = samples.begin() + static_cast<std::ptrdiff_t>(samples.size() / 2);
  std::nth_element(samples.begin(), middle, samples.end());
  return *middle;
}
