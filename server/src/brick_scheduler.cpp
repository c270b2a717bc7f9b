#include "brick_scheduler.h"

#include <boost/asio/post.hpp>

namespace soltex::server {

BrickScheduler::BrickScheduler(int threads)
    : threads_(threads), pool_(static_cast<std::size_t>(threads)) {}

BrickScheduler::~BrickScheduler() {
  stop();
}

void BrickScheduler::notify(const std::shared_ptr<WorkSource>& source, std::size_t items) {
  if (items == 0) return;
  {
    std::lock_guard lock(mutex_);
    if (!source->in_ready_list_) {
      source->in_ready_list_ = true;
      ready_.push_back(source);
    }
  }
  // One job per item: every item is picked up by some job, whichever stream it then serves.
  for (std::size_t i = 0; i < items; ++i) boost::asio::post(pool_, [this] { run_next(); });
}

void BrickScheduler::run_next() {
  std::function<void()> task;
  {
    std::lock_guard lock(mutex_);
    while (!task && !ready_.empty()) {
      std::shared_ptr<WorkSource> source = std::move(ready_.front());
      ready_.pop_front();
      task = source->take();
      if (source->has_work()) {
        ready_.push_back(std::move(source));  // back of the line: the other streams go first
      } else {
        source->in_ready_list_ = false;
      }
    }
  }
  // No task: the items this job was posted for were cancelled.
  if (task) task();
}

void BrickScheduler::stop() {
  pool_.join();
  timers_.join();  // a timer armed by a last delivery fires within its wait
  std::lock_guard lock(mutex_);
  for (auto& source : ready_) source->in_ready_list_ = false;
  ready_.clear();
}

}  // namespace soltex::server
