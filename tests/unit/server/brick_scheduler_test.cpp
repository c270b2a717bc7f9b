#include "brick_scheduler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

namespace soltex::server {
namespace {

// `count` tasks, each running `task`. take() and has_work() run under the scheduler's lock,
// so `left_` needs no lock of its own.
class CountedSource final : public WorkSource {
 public:
  CountedSource(int count, std::function<void()> task) : left_(count), task_(std::move(task)) {}
  std::function<void()> take() override {
    if (left_ == 0) return {};
    --left_;
    return task_;
  }
  bool has_work() const override { return left_ > 0; }

 private:
  int left_;
  std::function<void()> task_;
};

// Worker time as the tasks say it passed: each task advances this clock by what it claims
// to cost, so turns are shared by those costs whatever the machine's load does to real time.
class TaskClock {
 public:
  BrickScheduler::Clock clock() {
    return [this] { return now_ns_.load(); };
  }
  void spend(std::chrono::nanoseconds cost) { now_ns_ += cost.count(); }

 private:
  std::atomic<int64_t> now_ns_{0};
};

// Holds the first task back until every source of the test is queued, so the one worker
// cannot start before the test has set up what it compares.
class StartGate {
 public:
  void open() { opened_.set_value(); }
  void wait() const { opened_future_.wait(); }

 private:
  std::promise<void> opened_;
  std::shared_future<void> opened_future_ = opened_.get_future().share();
};

std::string as_text(const std::vector<char>& order) {
  return {order.begin(), order.end()};
}

TEST(BrickScheduler, TurnsAreSharedInWorkerTimeNotInTasks) {
  // One worker, a source of slow tasks (20 ms) and one of instant ones (1 us): counted in
  // tasks, turns would alternate; counted in time, the instant source's 400 tasks (0.4 ms in
  // all) all run before the slow source's second turn.
  TaskClock time;
  StartGate gate;
  BrickScheduler scheduler(1, 1.0, time.clock());
  int instant_done = 0;  // one worker: no lock needed
  std::vector<int> instant_done_at_slow_starts;
  auto slow = std::make_shared<CountedSource>(3, [&] {
    gate.wait();
    instant_done_at_slow_starts.push_back(instant_done);
    time.spend(std::chrono::milliseconds(20));
  });
  auto instant = std::make_shared<CountedSource>(400, [&] {
    ++instant_done;
    time.spend(std::chrono::microseconds(1));
  });
  scheduler.notify(slow, 3);
  scheduler.notify(instant, 400);
  gate.open();
  scheduler.stop();  // lets the workers finish what is queued
  ASSERT_EQ(instant_done_at_slow_starts.size(), 3u);
  EXPECT_EQ(instant_done_at_slow_starts[0], 0);
  EXPECT_EQ(instant_done_at_slow_starts[1], 400);
  EXPECT_EQ(instant_done, 400);
}

TEST(BrickScheduler, AnIdleSourceBanksNoCredit) {
  // A source that waited idle while another used the worker starts level with it: the two
  // then alternate instead of the newcomer taking every turn until it caught up.
  TaskClock time;
  BrickScheduler scheduler(1, 1.0, time.clock());
  std::vector<char> order;  // one worker: no lock needed
  std::shared_ptr<CountedSource> second = std::make_shared<CountedSource>(10, [&] {
    order.push_back('b');
    time.spend(std::chrono::milliseconds(2));
  });
  // `first` runs alone for 20 turns, then `second` comes: banked, those 40 ms would be 20
  // turns of credit, more than all of `second`'s 10.
  auto first = std::make_shared<CountedSource>(40, [&] {
    order.push_back('a');
    time.spend(std::chrono::milliseconds(2));
    if (order.size() == 20) scheduler.notify(second, 10);
  });
  scheduler.notify(first, 40);
  scheduler.stop();
  ASSERT_EQ(order.size(), 50u);
  int longest_b_run = 0;
  for (int i = 0, run = 0; i < static_cast<int>(order.size()); ++i) {
    run = order[static_cast<std::size_t>(i)] == 'b' ? run + 1 : 0;
    longest_b_run = std::max(longest_b_run, run);
  }
  EXPECT_EQ(as_text(order).substr(0, 20), std::string(20, 'a'));
  EXPECT_LE(longest_b_run, 2) << as_text(order);
}

TEST(BrickScheduler, TheSourcesOfOneClientShareOneClientsTurns) {
  // Client a has four sources, client b one, all with tasks of the same length: b gets half
  // the turns, not a fifth.
  TaskClock time;
  StartGate gate;
  BrickScheduler scheduler(1, 1.0, time.clock());
  std::vector<char> order;  // one worker: no lock needed
  const auto task_of = [&](char client) {
    return [&order, &time, &gate, client] {
      gate.wait();
      order.push_back(client);
      time.spend(std::chrono::milliseconds(2));
    };
  };
  std::vector<std::shared_ptr<CountedSource>> sources;
  for (int i = 0; i < 4; ++i) {
    sources.push_back(std::make_shared<CountedSource>(10, task_of('a')));
    sources.back()->share_with(scheduler.share_of("a"));
  }
  sources.push_back(std::make_shared<CountedSource>(40, task_of('b')));
  sources.back()->share_with(scheduler.share_of("b"));
  for (const auto& source : sources) scheduler.notify(source, 10);
  gate.open();
  scheduler.stop();
  ASSERT_EQ(order.size(), 80u);
  const auto b_turns = std::count(order.begin(), order.begin() + 40, 'b');
  EXPECT_GE(b_turns, 19) << as_text(order);  // 20 of 40, give or take the first turn
  EXPECT_LE(b_turns, 21) << as_text(order);
}

}  // namespace
}  // namespace soltex::server
