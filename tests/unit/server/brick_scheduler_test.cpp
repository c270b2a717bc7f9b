#include "brick_scheduler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>
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

TEST(BrickScheduler, TurnsAreSharedInWorkerTimeNotInTasks) {
  // One worker, a source of slow tasks (20 ms) and one of instant ones: counted in tasks,
  // turns would alternate; counted in time, the instant source's 400 tasks (well under 20 ms
  // in all) all run before the slow source's second turn.
  BrickScheduler scheduler(1);
  std::atomic<int> instant_done{0};
  std::vector<int> instant_done_at_slow_starts;  // one worker: no lock needed
  auto slow = std::make_shared<CountedSource>(3, [&] {
    instant_done_at_slow_starts.push_back(instant_done.load());
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  });
  auto instant = std::make_shared<CountedSource>(400, [&] { ++instant_done; });
  scheduler.notify(slow, 3);
  scheduler.notify(instant, 400);
  scheduler.stop();  // lets the workers finish what is queued
  ASSERT_EQ(instant_done_at_slow_starts.size(), 3u);
  EXPECT_LE(instant_done_at_slow_starts[0], 1);
  EXPECT_EQ(instant_done_at_slow_starts[1], 400);
  EXPECT_EQ(instant_done.load(), 400);
}

TEST(BrickScheduler, AnIdleSourceBanksNoCredit) {
  // A source that waited idle while another used the worker starts level with it: the two
  // then alternate instead of the newcomer taking every turn until it caught up.
  BrickScheduler scheduler(1);
  std::vector<char> order;  // one worker: no lock needed
  auto first = std::make_shared<CountedSource>(40, [&] {
    order.push_back('a');
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  });
  scheduler.notify(first, 10);
  // `first` runs alone a while: banked, that would be about 20 turns of credit, more than
  // `second` has.
  std::this_thread::sleep_for(std::chrono::milliseconds(40));
  auto second = std::make_shared<CountedSource>(10, [&] {
    order.push_back('b');
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  });
  scheduler.notify(second, 10);
  scheduler.stop();
  // Once `second` came, no run of its own longer than a few turns (a busy machine stretches
  // some turns: a little slack), where credit banked would run all 10 of them in a row.
  int longest_b_run = 0;
  for (int i = 0, run = 0; i < static_cast<int>(order.size()); ++i) {
    run = order[static_cast<std::size_t>(i)] == 'b' ? run + 1 : 0;
    longest_b_run = std::max(longest_b_run, run);
  }
  EXPECT_LE(longest_b_run, 4) << std::string(order.begin(), order.end());
  EXPECT_EQ(order.size(), 50u);
}

TEST(BrickScheduler, TheSourcesOfOneClientShareOneClientsTurns) {
  // Client a has four sources, client b one, all with tasks of the same length: b gets half
  // the turns, not a fifth.
  BrickScheduler scheduler(1);
  std::vector<char> order;  // one worker: no lock needed
  const auto task_of = [&](char client) {
    return [&order, client] {
      order.push_back(client);
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
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
  scheduler.stop();
  ASSERT_EQ(order.size(), 80u);
  const auto b_turns = std::count(order.begin(), order.begin() + 40, 'b');
  EXPECT_GE(b_turns, 16) << std::string(order.begin(), order.end());  // about 20 of 40
  EXPECT_LE(b_turns, 24) << std::string(order.begin(), order.end());
}

}  // namespace
}  // namespace soltex::server
