#include "brick_scheduler.h"

#include <algorithm>
#include <chrono>
#include <utility>

namespace soltex::server {

int64_t BrickScheduler::steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

BrickScheduler::BrickScheduler(int threads, double direct_request_share, Clock now_ns)
    : threads_(threads),
      now_ns_(std::move(now_ns)),
      direct_requests_(direct_request_share, std::chrono::milliseconds(5)) {
  workers_.reserve(static_cast<std::size_t>(threads));
  for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

BrickScheduler::~BrickScheduler() {
  stop();
}

void BrickScheduler::notify(const std::shared_ptr<WorkSource>& source, std::size_t items) {
  if (items == 0) return;
  std::size_t wakes = 0;
  {
    std::lock_guard lock(mutex_);
    if (!source->in_ready_list_) {
      source->in_ready_list_ = true;
      source->share_->used_ns = std::max(source->share_->used_ns, clock_ns_);
      ready_.push_back(source);
      waiting_sources_.store(ready_.size(), std::memory_order_relaxed);
    }
    // Busy workers come back for more by themselves; only sleeping ones need a wake-up.
    wakes = std::min(items, static_cast<std::size_t>(sleeping_));
  }
  if (wakes >= static_cast<std::size_t>(threads_)) {
    wake_.notify_all();
  } else {
    for (std::size_t i = 0; i < wakes; ++i) wake_.notify_one();
  }
}

std::shared_ptr<FairShare> BrickScheduler::share_of(const std::string& client) {
  std::lock_guard lock(mutex_);
  std::shared_ptr<FairShare> share = shares_[client].lock();
  if (!share) {
    // Clients come and go: forget the ones whose sources are all gone, now and then.
    if (shares_.size() > 1024)
      std::erase_if(shares_, [](const auto& s) { return s.second.expired(); });
    share = std::make_shared<FairShare>();
    share->used_ns = clock_ns_;
    shares_[client] = share;
  }
  return share;
}

BrickScheduler::Turn BrickScheduler::next_turn() {
  Turn turn;
  while (!turn.task && !ready_.empty()) {
    // The least used; among equals the longest waiting (the front), as round robin would.
    auto least = ready_.begin();
    for (auto it = ready_.begin(); it != ready_.end(); ++it) {
      if ((*it)->share_->used_ns < (*least)->share_->used_ns) least = it;
    }
    std::shared_ptr<WorkSource> source = std::move(*least);
    ready_.erase(least);
    clock_ns_ = std::max(clock_ns_, source->share_->used_ns);
    turn.task = source->take();
    if (source->has_work()) {
      ready_.push_back(source);
    } else {
      source->in_ready_list_ = false;
    }
    // Kept only with a task to charge: a source held by a sleeping worker would outlive its
    // stream (and its counts, which its destructor settles).
    if (turn.task) turn.source = std::move(source);
  }
  waiting_sources_.store(ready_.size(), std::memory_order_relaxed);
  return turn;
}

void BrickScheduler::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    Turn turn = next_turn();
    if (turn.task) {
      lock.unlock();
      const int64_t start_ns = now_ns_();
      turn.task();
      turn.task = nullptr;
      const int64_t used_ns = now_ns_() - start_ns;
      lock.lock();
      turn.source->share_->used_ns += used_ns;
      turn.source.reset();  // as next_turn() lets go of a source without work: under the lock
      continue;
    }
    if (stopping_) return;
    ++sleeping_;
    wake_.wait(lock);
    --sleeping_;
  }
}

void BrickScheduler::stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && workers_.empty()) return;
    stopping_ = true;
  }
  wake_.notify_all();
  for (std::thread& worker : workers_) {
    if (worker.joinable()) worker.join();
  }
  workers_.clear();
  timers_.join();  // a timer armed by a last delivery fires within its wait
  std::lock_guard lock(mutex_);
  for (auto& source : ready_) source->in_ready_list_ = false;
  ready_.clear();
  waiting_sources_.store(0, std::memory_order_relaxed);
}

}  // namespace soltex::server
