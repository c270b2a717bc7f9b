#pragma once

#include <functional>

#include "brick_store.h"
#include "fault_injection.h"
#include "server_metrics.h"
#include "shared_brick_cache.h"
#include "work_queue.h"

namespace soltex::server {

// Turns a wanted brick into an encoded one: from the store when cached, by waiting for whoever
// is already producing it, from the shared memcached tier when another replica made it, or by
// evaluating, quantizing and encoding it here (single flight) and writing it back there.
class BrickProducer {
 public:
  using Deliver = std::function<void(const EncodedBrickPtr&)>;  // nullptr: production failed

  // `shared` may be null (no second-level cache); `faults` may be null (none).
  BrickProducer(BrickStore& store, ServerMetrics& metrics, int zstd_level,
                SharedBrickCache* shared = nullptr, FaultInjection* faults = nullptr)
      : store_(store),
        metrics_(metrics),
        zstd_level_(zstd_level),
        shared_(shared),
        faults_(faults) {}

  // Calls `deliver` exactly once, on this thread or on the thread of the producing worker.
  void produce(const WorkItem& item, Deliver deliver);

  // The brick if the store holds it and may hand it out at once (not while fault injection
  // delays bricks); null otherwise. Cheap enough for a gRPC thread.
  EncodedBrickPtr cached(const BrickKey& key, Codec codec);

 private:
  EncodedBrickPtr from_shared_cache(const WorkItem& item);
  EncodedBrickPtr evaluate(const WorkItem& item);

  BrickStore& store_;
  ServerMetrics& metrics_;
  const int zstd_level_;
  SharedBrickCache* const shared_;
  FaultInjection* const faults_;
};

}  // namespace soltex::server
