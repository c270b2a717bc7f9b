#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <unordered_map>

namespace soltex::server {

// Warnings about refused calls, at most one line per client per interval: a client retrying
// a refused stream in a loop must not flood the log (or the disk). The next line written for
// that client says how many refusals were left out since its last line.
class RefusalLog {
 public:
  using Clock = std::chrono::steady_clock;
  // `write` receives each line (spdlog::warn in the daemon, a recorder in tests).
  explicit RefusalLog(std::function<void(const std::string&)> write,
                      Clock::duration interval = std::chrono::seconds(1));

  void refused(const std::string& client, const std::string& what, Clock::time_point now);
  void refused(const std::string& client, const std::string& what) {
    refused(client, what, Clock::now());
  }

  uint64_t suppressed() const;  // lines left out since the start

 private:
  struct Entry {
    Clock::time_point last_line;
    uint64_t suppressed = 0;
  };
  void forget_quiet_clients(Clock::time_point now);

  const std::function<void(const std::string&)> write_;
  const Clock::duration interval_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, Entry> clients_;
  Clock::time_point last_sweep_{};
  uint64_t suppressed_total_ = 0;
};

}  // namespace soltex::server
