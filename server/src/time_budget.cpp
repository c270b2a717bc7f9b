#include "time_budget.h"

#include <algorithm>

#include "soltex/common/check.h"

namespace soltex::server {

TimeBudget::TimeBudget(double share, std::chrono::nanoseconds burst)
    : share_(share),
      burst_ns_(burst.count()),
      credit_ns_(share > 0.0 ? burst.count() : 0),
      refilled_(Clock::now()) {
  SOLTEX_DCHECK(share >= 0.0 && burst.count() > 0);
}

bool TimeBudget::has_credit(Clock::time_point now) {
  if (share_ <= 0.0) return false;
  std::lock_guard lock(mutex_);
  refill(now);
  return credit_ns_ > 0;
}

void TimeBudget::spend(std::chrono::nanoseconds used) {
  std::lock_guard lock(mutex_);
  credit_ns_ -= used.count();
}

void TimeBudget::refill(Clock::time_point now) {
  if (now <= refilled_) return;
  const auto elapsed = std::chrono::duration_cast<std::chrono::nanoseconds>(now - refilled_);
  const auto earned = static_cast<int64_t>(share_ * static_cast<double>(elapsed.count()));
  credit_ns_ = std::min(burst_ns_, credit_ns_ + earned);
  refilled_ = now;
}

}  // namespace soltex::server
