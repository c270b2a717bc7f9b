#pragma once

#include <ctime>

namespace soltex {

// This process's CPU time so far, every thread included, in milliseconds: what work cost in
// cores. On a shared machine it hardly moves with the other load, where wall time grows by
// every time slice the work waited for.
inline double process_cpu_ms() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) / 1e6;
}

}  // namespace soltex
