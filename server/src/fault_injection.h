#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>

namespace soltex::server {

// Faults an operator can switch on to test clients against a misbehaving server. Off by
// default; soltexd logs a warning when any is on.
struct FaultConfig {
  int delay_ms = 0;            // every brick takes this much longer to make (a slow server)
  uint32_t corrupt_every = 0;  // every Nth brick sent has one payload byte flipped (0: never)
  bool any() const { return delay_ms > 0 || corrupt_every > 0; }
};

class FaultInjection {
 public:
  explicit FaultInjection(FaultConfig config) : config_(config) {}

  std::chrono::milliseconds delay() const { return std::chrono::milliseconds(config_.delay_ms); }

  // The delay of one brick, on the worker making it, as a slow evaluation would take it;
  // ended early by stop().
  void delay_brick() {
    if (config_.delay_ms <= 0) return;
    std::unique_lock lock(mutex_);
    stopped_changed_.wait_for(lock, delay(), [this] { return stopped_; });
  }
  // Ends every delay, now and later: once the shutdown grace is over, the bricks still queued
  // must not hold the workers (and the exit) a delay each.
  void stop() {
    {
      std::lock_guard lock(mutex_);
      stopped_ = true;
    }
    stopped_changed_.notify_all();
  }

  bool corrupts() const { return config_.corrupt_every > 0; }

  // Flips a byte of `payload` (a copy about to be sent) when this send is due for corruption.
  // The byte is past the header, so the client's checksum, not its header check, catches it.
  bool corrupt_if_due(std::string& payload) {
    if (config_.corrupt_every == 0 || payload.empty()) return false;
    if (sent_.fetch_add(1, std::memory_order_relaxed) % config_.corrupt_every !=
        config_.corrupt_every - 1) {
      return false;
    }
    payload[payload.size() - 1] = static_cast<char>(payload[payload.size() - 1] ^ 0x5A);
    corrupted_.fetch_add(1, std::memory_order_relaxed);
    return true;
  }

  uint64_t corrupted() const { return corrupted_.load(std::memory_order_relaxed); }

 private:
  const FaultConfig config_;
  std::mutex mutex_;
  std::condition_variable stopped_changed_;
  bool stopped_ = false;
  std::atomic<uint64_t> sent_{0};
  std::atomic<uint64_t> corrupted_{0};
};

}  // namespace soltex::server
