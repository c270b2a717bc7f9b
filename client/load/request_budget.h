#pragma once

#include <atomic>
#include <cstdint>
#include <optional>

namespace soltex::load {

// The measured requests a --count run may still make, shared by all streams.
class RequestBudget {
 public:
  explicit RequestBudget(std::optional<uint64_t> count)
      : limited_(count.has_value()), remaining_(count ? static_cast<int64_t>(*count) : 0) {}

  // Takes one request from the budget; false once it is spent.
  bool take() {
    if (!limited_) return true;
    return remaining_.fetch_sub(1, std::memory_order_relaxed) > 0;
  }
  bool exhausted() const { return limited_ && remaining_.load(std::memory_order_relaxed) <= 0; }

 private:
  const bool limited_;
  std::atomic<int64_t> remaining_;
};

}  // namespace soltex::load
