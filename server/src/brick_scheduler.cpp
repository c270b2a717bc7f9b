#include "brick_scheduler.h"

namespace soltex::server {

BrickScheduler::BrickScheduler(int threads) : threads_(threads) {
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

std::function<void()> BrickScheduler::next_task() {
  std::function<void()> task;
  while (!task && !ready_.empty()) {
    std::shared_ptr<WorkSource> source = std::move(ready_.front());
    ready_.pop_front();
    task = source->take();
    if (source->has_work()) {
      ready_.push_back(std::move(source));  // back of the line: the other sources go first
    } else {
      source->in_ready_list_ = false;
    }
  }
  waiting_sources_.store(ready_.size(), std::memory_order_relaxed);
  return task;
}

void BrickScheduler::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    std::function<void()> task = next_task();
    if (task) {
      lock.unlock();
      task();
      task = nullptr;  // let go of the source before taking the lock again
      lock.lock();
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
