#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <stop_token>
#include <thread>
#include <utility>
#include <vector>

// A fixed set of threads that run one parallel loop at a time. The calling thread works too,
// so a pool of one thread starts none. Indices are handed out one at a time (the loops here
// are over tiles and triangle chunks whose costs differ a lot), each thread first from its own
// contiguous share of the range and then from the others' shares: so a frame's tile i goes to
// the same thread as the last frame's, unless it was taken to even the load, and per-thread
// caches (the samplers' brick tables) find again what they held.
namespace soltex::raster_internal {

class WorkerPool {
 public:
  // `thread_count` >= 1, the caller included.
  explicit WorkerPool(int thread_count);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int thread_count() const { return static_cast<int>(threads_.size()) + 1; }

  // Calls task(index, worker) once for each index in [0, count), worker in
  // [0, thread_count()) naming the thread (for per-thread scratch); returns when all are done.
  // The first exception a task throws is rethrown here, after the others have stopped.
  void parallel_for(std::size_t count, const std::function<void(std::size_t, int)>& task);

 private:
  void worker_loop(const std::stop_token& stop, int worker);
  void run_tasks(int worker);

  std::mutex mutex_;
  std::condition_variable_any wake_;
  std::condition_variable done_;
  const std::function<void(std::size_t, int)>* task_ = nullptr;
  // One per thread: [next, end) of its share not yet handed out. Own cache lines: each
  // thread's counter is written by it on every index.
  struct alignas(64) Share {
    std::atomic<std::size_t> next{0};
    std::size_t end = 0;
  };
  std::unique_ptr<Share[]> shares_;
  unsigned long long generation_ = 0;
  int busy_workers_ = 0;
  std::exception_ptr error_;
  std::vector<std::jthread> threads_;  // last member: joined before the rest is destroyed
};

}  // namespace soltex::raster_internal
