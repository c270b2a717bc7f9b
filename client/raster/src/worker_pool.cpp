#include "worker_pool.h"

#include <algorithm>

namespace soltex::raster_internal {

WorkerPool::WorkerPool(int thread_count)
    : shares_(std::make_unique<Share[]>(static_cast<std::size_t>(std::max(thread_count, 1)))) {
  for (int worker = 1; worker < thread_count; ++worker) {
    threads_.emplace_back([this, worker](std::stop_token stop) { worker_loop(stop, worker); });
  }
}

WorkerPool::~WorkerPool() {
  for (std::jthread& thread : threads_) thread.request_stop();
  wake_.notify_all();
  threads_.clear();  // joins
}

void WorkerPool::parallel_for(std::size_t count,
                              const std::function<void(std::size_t, int)>& task) {
  if (count == 0) return;
  {
    std::lock_guard lock(mutex_);
    task_ = &task;
    const auto threads = static_cast<std::size_t>(thread_count());
    for (std::size_t w = 0; w < threads; ++w) {
      shares_[w].next.store(count * w / threads, std::memory_order_relaxed);
      shares_[w].end = count * (w + 1) / threads;
    }
    error_ = nullptr;
    busy_workers_ = static_cast<int>(threads_.size());
    ++generation_;
  }
  wake_.notify_all();
  run_tasks(0);
  std::unique_lock lock(mutex_);
  done_.wait(lock, [this] { return busy_workers_ == 0; });
  task_ = nullptr;
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void WorkerPool::worker_loop(const std::stop_token& stop, int worker) {
  unsigned long long seen = 0;
  while (true) {
    {
      std::unique_lock lock(mutex_);
      if (!wake_.wait(lock, stop, [&] { return generation_ != seen; })) return;
      seen = generation_;
    }
    run_tasks(worker);
    std::lock_guard lock(mutex_);
    if (--busy_workers_ == 0) done_.notify_one();
  }
}

void WorkerPool::run_tasks(int worker) {
  const auto threads = static_cast<std::size_t>(thread_count());
  for (std::size_t k = 0; k < threads; ++k) {
    Share& share = shares_[(static_cast<std::size_t>(worker) + k) % threads];
    while (true) {
      const std::size_t index = share.next.fetch_add(1, std::memory_order_relaxed);
      if (index >= share.end) break;
      try {
        (*task_)(index, worker);
      } catch (...) {
        std::lock_guard lock(mutex_);
        if (!error_) error_ = std::current_exception();
        // The others stop at their next index.
        for (std::size_t w = 0; w < threads; ++w) {
          shares_[w].next.store(shares_[w].end, std::memory_order_relaxed);
        }
      }
    }
  }
}

}  // namespace soltex::raster_internal
