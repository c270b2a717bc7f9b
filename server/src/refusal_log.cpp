#include "refusal_log.h"

namespace soltex::server {
namespace {

// Clients tracked before quiet ones are forgotten; bounds the map when many addresses refuse.
constexpr std::size_t kMaxTrackedClients = 4096;
// Beyond that many even after forgetting, new clients share one entry (and one line a second).
constexpr const char* kOverflowClient = "(other clients)";

}  // namespace

RefusalLog::RefusalLog(std::function<void(const std::string&)> write, Clock::duration interval)
    : write_(std::move(write)), interval_(interval) {}

void RefusalLog::refused(const std::string& client, const std::string& what,
                         Clock::time_point now) {
  std::string line;
  {
    std::lock_guard lock(mutex_);
    if (clients_.size() >= kMaxTrackedClients && !clients_.contains(client)) {
      forget_quiet_clients(now);
    }
    const bool overflow = clients_.size() >= kMaxTrackedClients && !clients_.contains(client);
    auto [it, fresh] = clients_.try_emplace(overflow ? kOverflowClient : client);
    Entry& entry = it->second;
    if (!fresh && now - entry.last_line < interval_) {
      ++entry.suppressed;
      ++suppressed_total_;
      return;
    }
    line = what;
    if (entry.suppressed > 0) {
      line += " (" + std::to_string(entry.suppressed) + " more refusals of " + client +
              " not logged since its last line)";
    }
    entry = {now, 0};
  }
  write_(line);
}

void RefusalLog::forget_quiet_clients(Clock::time_point now) {
  // At most one sweep an interval: many new clients at once must not each pay for one.
  if (last_sweep_ != Clock::time_point{} && now - last_sweep_ < interval_) return;
  last_sweep_ = now;
  // Clients without a line for an interval lose their entry; a count they had suppressed is
  // then not reported on a line of theirs, but stays in suppressed().
  std::erase_if(clients_,
                [&](const auto& entry) { return now - entry.second.last_line >= interval_; });
}

uint64_t RefusalLog::suppressed() const {
  std::lock_guard lock(mutex_);
  return suppressed_total_;
}

}  // namespace soltex::server
