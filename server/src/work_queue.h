#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <set>
#include <unordered_map>

#include "brick_store.h"
#include "texture_registry.h"

namespace soltex::server {

// A brick a stream is waiting for.
struct WorkItem {
  BrickKey key;
  int32_t priority = 0;
  Codec codec = Codec::zstd;
  TexturePtr texture;
  std::chrono::steady_clock::time_point enqueued;
  uint64_t sequence = 0;  // arrival order, the last tie-breaker
};

// One stream's pending bricks, best first: coarser levels first (a coarse brick is a fallback
// for many fine ones), then higher client priority, then arrival order. A key is queued at
// most once; asking again raises its priority. Thread-safe.
//
// It also counts the items taken and not yet finished, under the same lock as the queue: an
// item is always either queued or taken until finished(), so drained() cannot see it in
// neither (a stream that looked at two separate counters could finish between a worker's pop
// and its count, and drop the brick).
class WorkQueue {
 public:
  enum class Push { added, updated };
  Push push(WorkItem item);
  bool cancel(const BrickKey& key);
  // The best item, now counted as taken; nullopt when none is queued.
  std::optional<WorkItem> pop();
  // A taken item is done with (its brick made, or its failure reported).
  void finished();
  // A taken item goes back unmade, in its old place (its sequence); if its key was asked for
  // again meanwhile, the queued one stands. Returns whether it was queued again.
  bool give_back(WorkItem item);
  // A key still queued takes `priority` if higher (as push() does) and true is returned;
  // false, and nothing queued, when it is not queued.
  bool merge(const BrickKey& key, int32_t priority);
  std::size_t size() const;         // queued
  std::size_t taken() const;        // taken and not finished
  std::size_t outstanding() const;  // queued + taken, read together
  bool drained() const;             // nothing queued and nothing taken
  std::size_t clear();              // drops the queued items (not the taken ones); returns how many

 private:
  struct Order {
    bool operator()(const WorkItem& a, const WorkItem& b) const {
      if (a.key.level != b.key.level) return a.key.level > b.key.level;
      if (a.priority != b.priority) return a.priority > b.priority;
      return a.sequence < b.sequence;
    }
  };
  using Set = std::set<WorkItem, Order>;

  bool merge_locked(const BrickKey& key, int32_t priority);

  mutable std::mutex mutex_;
  Set items_;
  std::unordered_map<BrickKey, Set::iterator, BrickKeyHash> by_key_;
  uint64_t next_sequence_ = 0;
  std::size_t taken_ = 0;
};

}  // namespace soltex::server
