#include "warning_throttle.h"

#include <gtest/gtest.h>

#include <thread>

namespace soltex::net {
namespace {

TEST(WarningThrottle, WritesAFewLinesASecondAndCountsTheRest) {
  WarningThrottle throttle;
  int written = 0;
  for (int i = 0; i < 3 * WarningThrottle::kLinesPerSecond; ++i) {
    uint64_t held_back = 99;
    if (throttle.allow(held_back)) {
      ++written;
      EXPECT_EQ(held_back, 0u);
    }
  }
  EXPECT_EQ(written, WarningThrottle::kLinesPerSecond);
  WarningThrottle ended;
  uint64_t ignored = 0;
  for (int i = 0; i < WarningThrottle::kLinesPerSecond + 3; ++i) (void)ended.allow(ignored);
  EXPECT_EQ(ended.take_held_back(), 3u);
  EXPECT_EQ(ended.take_held_back(), 0u);
  // A new second: the next line is written and says how many were not.
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  uint64_t held_back = 0;
  ASSERT_TRUE(throttle.allow(held_back));
  EXPECT_EQ(held_back, static_cast<uint64_t>(2 * WarningThrottle::kLinesPerSecond));
  ASSERT_TRUE(throttle.allow(held_back));
  EXPECT_EQ(held_back, 0u);
}

}  // namespace
}  // namespace soltex::net
