#pragma once

#include <atomic>
#include <boost/asio/thread_pool.hpp>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "time_budget.h"

namespace soltex::server {

// The worker time a client's turns have taken, shared by all its sources (its streams), so
// that fairness is between clients: one client's 64 streams get one client's share. Guarded
// by the scheduler's mutex.
struct FairShare {
  int64_t used_ns = 0;
};

// Something with bricks to make: a stream. The scheduler asks it for one item at a time.
class WorkSource {
 public:
  virtual ~WorkSource() = default;
  // Charges this source's turns to `share` (BrickScheduler::share_of its client) instead of
  // an account of its own. Before it is first notified.
  void share_with(std::shared_ptr<FairShare> share) { share_ = std::move(share); }
  // Takes the best pending item (or a short run of them, best first) off the queue and returns
  // the work to do for it (run by the scheduler outside its lock), or an empty function when
  // nothing is pending. Called with
  // the scheduler's lock held: keep it short.
  virtual std::function<void()> take() = 0;
  virtual bool has_work() const = 0;

 private:
  friend class BrickScheduler;
  bool in_ready_list_ = false;  // guarded by the scheduler's mutex
  std::shared_ptr<FairShare> share_ = std::make_shared<FairShare>();
};

// Brick work runs on our own worker threads, never on gRPC's threads. Fair across clients in
// worker time, not in bricks: the next turn goes to the waiting source whose client's turns
// have taken the least time (a client that was idle starts level with the one served last,
// so idling banks no credit). A texture whose bricks take a second each then gets the same share of
// the workers as one whose bricks take 0.2 ms, where turns counted in bricks gave it 5,000 times
// more. A turn is one take(): one item, a run of a few when many sources wait, or the handling
// of a request a stream read, so that a client's request parsing is charged to it as well;
// within a stream the source's own order decides (coarse levels first, then priority).
//
// A worker keeps taking items until no source has any, so a busy server hands bricks to its
// workers without a wake-up per brick: a worker sleeps only when there is nothing to do, and
// notify() wakes no more sleeping workers than there are new items.
class BrickScheduler {
 public:
  // What a turn's worker time is read from, in nanoseconds: the steady clock, or in a test
  // a clock its tasks advance, so that fairness is checked without timing real work.
  using Clock = std::function<int64_t()>;
  static int64_t steady_now_ns();

  // direct_request_share: the threads' worth of time of direct_requests().
  explicit BrickScheduler(int threads, double direct_request_share = 1.0,
                          Clock now_ns = &BrickScheduler::steady_now_ns);
  ~BrickScheduler();

  // `source` gained `items` new items of work.
  void notify(const std::shared_ptr<WorkSource>& source, std::size_t items);

  // The account of `client`'s sources: one per client while any source of it holds it.
  std::shared_ptr<FairShare> share_of(const std::string& client);

  // Lets the workers finish what is queued, then joins them.
  void stop();
  int threads() const { return threads_; }
  // Sources with work waiting for a worker, as of a moment ago (no lock: a hint).
  std::size_t waiting_sources() const { return waiting_sources_.load(std::memory_order_relaxed); }
  // The time gRPC's threads may spend handling requests (parsing, queueing, answering from
  // the cache) before further requests wait for a worker's turn, charged to their client like
  // bricks: handled there, one client's flood of requests would keep gRPC's few threads busy
  // while other clients' messages waited, unread, behind it. A whole thread by default: a
  // hot-cache client alone keeps the direct path (a worker hand-off per request cost 35 % of
  // hot serving's rate), and a flood leaves gRPC's other threads to everyone's I/O.
  TimeBudget& direct_requests() { return direct_requests_; }
  // An executor for short handlers such as timers, on a thread of its own: the workers may all
  // be busy with bricks for longer than a timer should wait.
  boost::asio::thread_pool::executor_type timer_executor() { return timers_.get_executor(); }

 private:
  void work();
  struct Turn {
    std::function<void()> task;  // empty when no source has work
    std::shared_ptr<WorkSource> source;
  };
  // The next turn: the waiting source that has used the least worker time. mutex_ held.
  Turn next_turn();

  const int threads_;
  const Clock now_ns_;
  boost::asio::thread_pool timers_{1};
  TimeBudget direct_requests_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::shared_ptr<WorkSource>> ready_;
  std::atomic<std::size_t> waiting_sources_{0};  // ready_.size(), readable without the lock
  int64_t clock_ns_ = 0;  // used_ns of the share served last: where a newly waiting one starts
  std::unordered_map<std::string, std::weak_ptr<FairShare>> shares_;  // by client
  int sleeping_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace soltex::server
