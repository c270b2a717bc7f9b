#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "brick_producer.h"
#include "brick_scheduler.h"

namespace soltex::server {

// The HTTP endpoint's bricks waiting for a worker: one WorkSource for every HTTP request, so
// the scheduler gives HTTP one turn in the round robin beside each gRPC stream. Coarser levels
// first (a viewer draws them as fallbacks for finer ones), then arrival order. Unlike a
// stream's WorkQueue a key may be queued twice (two clients asking at once): the brick store's
// single flight makes it once.
class HttpBrickQueue final : public WorkSource,
                             public std::enable_shared_from_this<HttpBrickQueue> {
 public:
  HttpBrickQueue(BrickScheduler& scheduler, BrickProducer& producer)
      : scheduler_(scheduler), producer_(producer) {}

  // `deliver` is called once, on a worker thread (nullptr: production failed).
  void submit(WorkItem item, BrickProducer::Deliver deliver);

  std::function<void()> take() override;
  bool has_work() const override;

 private:
  using Order = std::pair<int, uint64_t>;  // (-level, arrival)
  BrickScheduler& scheduler_;
  BrickProducer& producer_;
  mutable std::mutex mutex_;
  std::multimap<Order, std::pair<WorkItem, BrickProducer::Deliver>> jobs_;
  uint64_t arrivals_ = 0;
};

}  // namespace soltex::server
