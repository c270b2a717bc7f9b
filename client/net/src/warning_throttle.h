#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>

namespace soltex::net {

// At most kLinesPerSecond warnings of one kind a second: a server that corrupts or refuses
// every brick would otherwise write a line per brick (thousands a frame), burying the rest
// of the log. What is held back is counted and said with the next line written.
class WarningThrottle {
 public:
  static constexpr int kLinesPerSecond = 5;

  // Whether a line may be written now; if so, `held_back` is how many were not written since
  // the last one that was.
  bool allow(uint64_t& held_back);

  // The lines not written since the last one that was, now zero: said once at the end.
  uint64_t take_held_back();

 private:
  std::mutex mutex_;
  std::chrono::steady_clock::time_point window_start_{};
  int written_in_window_ = 0;
  uint64_t held_back_ = 0;
};

}  // namespace soltex::net
