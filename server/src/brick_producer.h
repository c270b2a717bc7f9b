#pragma once

#include <functional>

#include "brick_store.h"
#include "server_metrics.h"
#include "work_queue.h"

namespace soltex::server {

// Turns a wanted brick into an encoded one: from the store when cached, by waiting for whoever
// is already producing it, or by evaluating, quantizing and encoding it here (single flight).
class BrickProducer {
 public:
  using Deliver = std::function<void(const EncodedBrickPtr&)>;  // nullptr: production failed

  BrickProducer(BrickStore& store, ServerMetrics& metrics, int zstd_level)
      : store_(store), metrics_(metrics), zstd_level_(zstd_level) {}

  // Calls `deliver` exactly once, on this thread or on the thread of the producing worker.
  void produce(const WorkItem& item, Deliver deliver);

 private:
  EncodedBrickPtr evaluate(const WorkItem& item);

  BrickStore& store_;
  ServerMetrics& metrics_;
  const int zstd_level_;
};

}  // namespace soltex::server
