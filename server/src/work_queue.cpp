#include "work_queue.h"

#include <cassert>

namespace soltex::server {

WorkQueue::Push WorkQueue::push(WorkItem item) {
  std::lock_guard lock(mutex_);
  if (merge_locked(item.key, item.priority)) return Push::updated;
  item.sequence = next_sequence_++;
  const BrickKey key = item.key;
  by_key_.emplace(key, items_.insert(std::move(item)).first);
  return Push::added;
}

bool WorkQueue::cancel(const BrickKey& key) {
  std::lock_guard lock(mutex_);
  auto it = by_key_.find(key);
  if (it == by_key_.end()) return false;
  items_.erase(it->second);
  by_key_.erase(it);
  return true;
}

std::optional<WorkItem> WorkQueue::pop() {
  std::lock_guard lock(mutex_);
  if (items_.empty()) return std::nullopt;
  auto node = items_.extract(items_.begin());
  by_key_.erase(node.value().key);
  ++taken_;
  return std::move(node.value());
}

bool WorkQueue::give_back(WorkItem item) {
  std::lock_guard lock(mutex_);
  assert(taken_ > 0 && "give_back() without a pop()");
  if (taken_ > 0) --taken_;
  if (by_key_.contains(item.key)) return false;
  const BrickKey key = item.key;
  by_key_.emplace(key, items_.insert(std::move(item)).first);
  return true;
}

void WorkQueue::finished() {
  std::lock_guard lock(mutex_);
  assert(taken_ > 0 && "finished() without a pop()");
  if (taken_ > 0) --taken_;
}

bool WorkQueue::merge(const BrickKey& key, int32_t priority) {
  std::lock_guard lock(mutex_);
  return merge_locked(key, priority);
}

bool WorkQueue::merge_locked(const BrickKey& key, int32_t priority) {
  const auto it = by_key_.find(key);
  if (it == by_key_.end()) return false;
  if (priority <= it->second->priority) return true;
  WorkItem updated = *it->second;
  updated.priority = priority;
  items_.erase(it->second);
  it->second = items_.insert(std::move(updated)).first;
  return true;
}

std::size_t WorkQueue::size() const {
  std::lock_guard lock(mutex_);
  return items_.size();
}

std::size_t WorkQueue::taken() const {
  std::lock_guard lock(mutex_);
  return taken_;
}

std::size_t WorkQueue::outstanding() const {
  std::lock_guard lock(mutex_);
  return items_.size() + taken_;
}

bool WorkQueue::drained() const {
  std::lock_guard lock(mutex_);
  return items_.empty() && taken_ == 0;
}

std::size_t WorkQueue::clear() {
  std::lock_guard lock(mutex_);
  const std::size_t n = items_.size();
  items_.clear();
  by_key_.clear();
  return n;
}

}  // namespace soltex::server
