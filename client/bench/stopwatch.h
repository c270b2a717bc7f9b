#pragma once

#include <chrono>

#include "soltex/common/process_cpu_time.h"

namespace soltex::bench {

// Wall and CPU time of one piece of work, in milliseconds.
struct Elapsed {
  double wall_ms = 0.0;
  // CPU time of the whole process, every thread included (a frame's render threads too;
  // soltex::process_cpu_ms).
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
  std::chrono::steady_clock::time_point wall_start_;
  double cpu_start_;
};

}  // namespace soltex::bench
