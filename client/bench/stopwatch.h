#pragma once

#include <time.h>

#include <chrono>

namespace soltex::bench {

// Wall and CPU time of one piece of work, in milliseconds.
struct Elapsed {
  double wall_ms = 0.0;
  // CPU time of the whole process, every thread included (a frame's render threads too):
  // what the work cost in cores. On a shared machine it hardly moves with the other load,
  // where the wall time grows by every time slice the work waited for.
  double cpu_ms = 0.0;
};

class Stopwatch {
 public:
  Stopwatch() : wall_start_(std::chrono::steady_clock::now()), cpu_start_(process_cpu_ms()) {}

  Elapsed elapsed() const {
    return {
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start_)
            .count(),
        process_cpu_ms() - cpu_start_};
  }

 private:
  static double process_cpu_ms() {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) / 1e6;
  }

  std::chrono::steady_clock::time_point wall_start_;
  double cpu_start_;
};

}  // namespace soltex::bench
