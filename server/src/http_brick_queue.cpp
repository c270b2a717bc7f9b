#include "http_brick_queue.h"

namespace soltex::server {

void HttpBrickQueue::submit(WorkItem item, BrickProducer::Deliver deliver) {
  {
    std::lock_guard lock(mutex_);
    const Order order{-item.key.level, arrivals_++};
    jobs_.emplace(order, std::make_pair(std::move(item), std::move(deliver)));
  }
  scheduler_.notify(shared_from_this(), 1);
}

std::function<void()> HttpBrickQueue::take() {
  std::lock_guard lock(mutex_);
  if (jobs_.empty()) return {};
  auto job = std::move(jobs_.begin()->second);
  jobs_.erase(jobs_.begin());
  return [self = shared_from_this(), job = std::move(job)] {
    self->producer_.produce(job.first, job.second);
  };
}

bool HttpBrickQueue::has_work() const {
  std::lock_guard lock(mutex_);
  return !jobs_.empty();
}

}  // namespace soltex::server
