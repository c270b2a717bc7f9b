#pragma once

#include <boost/asio/thread_pool.hpp>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>

namespace soltex::server {

// Something with bricks to make: a stream. The scheduler asks it for one item at a time.
class WorkSource {
 public:
  virtual ~WorkSource() = default;
  // Takes the best pending item off the queue and returns the work to do for it (run by the
  // scheduler outside its lock), or an empty function when nothing is pending. Called with
  // the scheduler's lock held: keep it short.
  virtual std::function<void()> take() = 0;
  virtual bool has_work() const = 0;

 private:
  friend class BrickScheduler;
  bool in_ready_list_ = false;  // guarded by the scheduler's mutex
};

// Brick work runs on our own thread pool, never on gRPC's threads. Fair across streams:
// sources with work take turns, one item each (round robin); within a stream the source's
// own order decides (coarse levels first, then priority).
class BrickScheduler {
 public:
  explicit BrickScheduler(int threads);
  ~BrickScheduler();

  // `source` gained `items` new items of work.
  void notify(const std::shared_ptr<WorkSource>& source, std::size_t items);

  // Lets queued jobs finish and joins the workers.
  void stop();
  int threads() const { return threads_; }
  // An executor for short handlers such as timers, on a thread of its own: the workers may all
  // be busy with bricks for longer than a timer should wait.
  boost::asio::thread_pool::executor_type timer_executor() { return timers_.get_executor(); }

 private:
  void run_next();

  const int threads_;
  boost::asio::thread_pool pool_;
  boost::asio::thread_pool timers_{1};
  std::mutex mutex_;
  std::deque<std::shared_ptr<WorkSource>> ready_;
};

}  // namespace soltex::server
