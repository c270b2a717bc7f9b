#include "warning_throttle.h"

namespace soltex::net {

bool WarningThrottle::allow(uint64_t& held_back) {
  const auto now = std::chrono::steady_clock::now();
  std::lock_guard lock(mutex_);
  if (now - window_start_ >= std::chrono::seconds(1)) {
    window_start_ = now;
    written_in_window_ = 0;
  }
  if (written_in_window_ >= kLinesPerSecond) {
    ++held_back_;
    return false;
  }
  ++written_in_window_;
  held_back = held_back_;
  held_back_ = 0;
  return true;
}

uint64_t WarningThrottle::take_held_back() {
  std::lock_guard lock(mutex_);
  const uint64_t held_back = held_back_;
  held_back_ = 0;
  return held_back;
}

}  // namespace soltex::net
