#include "accept_retry.h"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace soltex::server {

AcceptRetry::AcceptRetry(const boost::asio::any_io_executor& executor, std::string listener)
    : timer_(executor), listener_(std::move(listener)) {}

void AcceptRetry::failed(const boost::system::error_code& error,
                         std::function<void()> accept_again) {
  const Clock::time_point now = Clock::now();
  if (failures_++ == 0) burst_start_ = now;
  ++unlogged_;
  // At the edge of the limit accepts fail and work by turns: a line a minute at most.
  if (!logged_once_ || now - last_line_ >= kLogInterval) {
    if (unlogged_ == 1) {
      spdlog::warn(
          "accepting {} connections failed: {}; trying again within {} ms until it works "
          "(out of file descriptors? compare process_open_fds with process_max_fds)",
          listener_, error.message(), kLongestPause.count());
    } else {
      spdlog::warn("accepting {} connections failed again: {} ({} failures since the last line)",
                   listener_, error.message(), unlogged_);
    }
    logged_once_ = true;
    burst_logged_ = true;
    last_line_ = now;
    unlogged_ = 0;
  }
  timer_.expires_after(pause_);
  pause_ = std::min(pause_ * 2, kLongestPause);
  timer_.async_wait([accept_again = std::move(accept_again)](boost::system::error_code ec) {
    if (!ec) accept_again();  // cancelled: stopping
  });
}

void AcceptRetry::succeeded() {
  if (failures_ == 0) return;
  if (burst_logged_) {
    const auto lasted = std::chrono::duration<double>(Clock::now() - burst_start_).count();
    spdlog::info("accepting {} connections works again, after {} failures over {:.1f} s", listener_,
                 failures_, lasted);
  }
  failures_ = 0;
  burst_logged_ = false;
  pause_ = kFirstPause;
}

void AcceptRetry::cancel() {
  timer_.cancel();
}

}  // namespace soltex::server
