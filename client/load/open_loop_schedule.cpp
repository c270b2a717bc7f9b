#include "open_loop_schedule.h"

#include <stdexcept>

namespace soltex::load {

OpenLoopSchedule OpenLoopSchedule::fixed_rate(double bricks_per_second) {
  if (!(bricks_per_second > 0.0)) throw std::invalid_argument("open-loop rate must be > 0");
  OpenLoopSchedule schedule;
  schedule.interval_ = 1.0 / bricks_per_second;
  return schedule;
}

OpenLoopSchedule OpenLoopSchedule::recorded(const std::vector<RecordedRequest>& log, double speed) {
  if (log.empty()) throw std::invalid_argument("the replay log has no requests");
  if (!(speed > 0.0)) throw std::invalid_argument("replay speed must be > 0");
  OpenLoopSchedule schedule;
  const double start = log.front().seconds;
  for (const RecordedRequest& r : log) schedule.times_.push_back((r.seconds - start) / speed);
  const double span = schedule.times_.back();
  const double mean_gap = log.size() > 1 ? span / static_cast<double>(log.size() - 1) : 0.0;
  // Without a time span the schedule would send every request at once, without end.
  if (!(span > 0.0)) {
    throw std::invalid_argument(
        "a replay log needs requests at two or more distinct times to "
        "be replayed at its recorded times");
  }
  schedule.period_ = span + mean_gap;
  return schedule;
}

double OpenLoopSchedule::seconds(uint64_t i) const {
  if (times_.empty()) return static_cast<double>(i) * interval_;
  const uint64_t n = times_.size();
  return static_cast<double>(i / n) * period_ + times_[i % n];
}

}  // namespace soltex::load
