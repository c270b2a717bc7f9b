#include "work_queue.h"

#include <gtest/gtest.h>

namespace soltex::server {
namespace {

WorkItem item_at(int level, int x, int32_t priority = 0) {
  WorkItem item;
  item.key = BrickKey{7, level, glm::ivec3(x, 0, 0)};
  item.priority = priority;
  return item;
}

TEST(WorkQueue, CoarserLevelsThenPriorityThenArrival) {
  WorkQueue queue;
  queue.push(item_at(0, 1));
  queue.push(item_at(0, 2, 5));
  queue.push(item_at(2, 3));
  queue.push(item_at(0, 4));
  EXPECT_EQ(queue.pop()->key.brick.x, 3);  // the coarsest level first
  EXPECT_EQ(queue.pop()->key.brick.x, 2);  // then the higher priority
  EXPECT_EQ(queue.pop()->key.brick.x, 1);  // then arrival order
  EXPECT_EQ(queue.pop()->key.brick.x, 4);
  EXPECT_FALSE(queue.pop());
}

TEST(WorkQueue, AnItemIsQueuedOrTakenUntilFinished) {
  WorkQueue queue;
  EXPECT_TRUE(queue.drained());
  queue.push(item_at(0, 1));
  queue.push(item_at(0, 2));
  EXPECT_EQ(queue.size(), 2u);
  EXPECT_FALSE(queue.drained());

  ASSERT_TRUE(queue.pop());
  EXPECT_EQ(queue.size(), 1u);
  EXPECT_EQ(queue.taken(), 1u);
  // Clearing drops what is queued, not what a worker is making.
  EXPECT_EQ(queue.clear(), 1u);
  EXPECT_EQ(queue.size(), 0u);
  EXPECT_EQ(queue.taken(), 1u);
  EXPECT_FALSE(queue.drained());

  EXPECT_EQ(queue.outstanding(), 1u);
  queue.finished();
  EXPECT_EQ(queue.taken(), 0u);
  EXPECT_EQ(queue.outstanding(), 0u);
  EXPECT_TRUE(queue.drained());
}

TEST(WorkQueue, AskingAgainRaisesPriorityWithoutQueueingTwice) {
  WorkQueue queue;
  EXPECT_EQ(queue.push(item_at(0, 1)), WorkQueue::Push::added);
  EXPECT_EQ(queue.push(item_at(0, 2)), WorkQueue::Push::added);
  EXPECT_EQ(queue.push(item_at(0, 2, 9)), WorkQueue::Push::updated);
  EXPECT_EQ(queue.size(), 2u);
  EXPECT_EQ(queue.pop()->key.brick.x, 2);
  EXPECT_TRUE(queue.cancel(item_at(0, 1).key));
  EXPECT_FALSE(queue.cancel(item_at(0, 1).key));
  EXPECT_EQ(queue.size(), 0u);
  EXPECT_EQ(queue.taken(), 1u);  // the popped one, until finished()
}

}  // namespace
}  // namespace soltex::server
