#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/system/error_code.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

namespace soltex::server {

// What an Asio listener does when accepting fails for a reason other than being closed: out
// of file descriptors (EMFILE, ENFILE), or of memory. The failed connection stays in the
// backlog, so the accept must be armed again or the listener is dead while the process
// lives; it is, after a pause that grows while the failures last (the error would otherwise
// come back at once, spinning a thread). A failure is logged at most once a minute, with the
// count left out since, and the end of a burst whose failure was logged is logged too.
class AcceptRetry {
 public:
  using Clock = std::chrono::steady_clock;
  // `listener` names it in the log ("metrics", "HTTP").
  AcceptRetry(const boost::asio::any_io_executor& executor, std::string listener);

  // After a failed accept: logs (at most once a minute) and calls `accept_again` after the pause,
  // on the executor. Nothing once cancel() is called.
  void failed(const boost::system::error_code& error, std::function<void()> accept_again);
  // After an accept that worked: ends a burst.
  void succeeded();
  void cancel();

  static constexpr std::chrono::milliseconds kFirstPause{50};
  static constexpr std::chrono::milliseconds kLongestPause{1000};
  static constexpr std::chrono::seconds kLogInterval{60};

 private:
  boost::asio::steady_timer timer_;
  const std::string listener_;
  // Touched by one accept's handler at a time: accepts on one acceptor do not overlap.
  uint64_t failures_ = 0;  // in this burst
  uint64_t unlogged_ = 0;  // failures since the last line
  bool logged_once_ = false;
  bool burst_logged_ = false;
  Clock::time_point burst_start_{};
  Clock::time_point last_line_{};
  std::chrono::milliseconds pause_ = kFirstPause;
};

}  // namespace soltex::server
