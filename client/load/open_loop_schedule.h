#pragma once

#include <cstdint>
#include <vector>

#include "request_log.h"

namespace soltex::load {

// When an open-loop run means to send its i-th request, in seconds from the start of the
// load. Requests are sent at these times whether or not earlier ones have been answered, and
// their latency counts from here, so a slow server cannot hide its queueing by slowing the
// sender down (coordinated omission).
class OpenLoopSchedule {
 public:
  // Request i at i / rate.
  static OpenLoopSchedule fixed_rate(double bricks_per_second);
  // Request i at the recorded time of log entry i divided by `speed`; after the last entry
  // the log starts again, one mean gap after its last time.
  static OpenLoopSchedule recorded(const std::vector<RecordedRequest>& log, double speed);

  double seconds(uint64_t i) const;

 private:
  OpenLoopSchedule() = default;

  double interval_ = 0.0;      // fixed rate
  std::vector<double> times_;  // recorded, already divided by the speed
  double period_ = 0.0;        // recorded: time of one pass through the log
};

}  // namespace soltex::load
