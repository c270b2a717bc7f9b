#include "time_budget.h"

#include <gtest/gtest.h>

#include <chrono>

namespace soltex::server {
namespace {

using std::chrono::milliseconds;

TEST(TimeBudget, WorkStartsWhileCreditLastsAndIsSpentAfterwards) {
  TimeBudget budget(1.0, milliseconds(5));
  const auto start = TimeBudget::Clock::now();
  EXPECT_TRUE(budget.has_credit(start));
  // Work that overran the credit still starts; what it took is owed.
  budget.spend(milliseconds(12));
  EXPECT_FALSE(budget.has_credit(start));
  // At one second per second, 7 ms of debt is repaid after 7 ms, not before.
  EXPECT_FALSE(budget.has_credit(start + milliseconds(6)));
  EXPECT_TRUE(budget.has_credit(start + milliseconds(8)));
}

TEST(TimeBudget, CreditComesBackAtItsShareUpToTheBurst) {
  TimeBudget budget(0.25, milliseconds(4));
  const auto start = TimeBudget::Clock::now();
  ASSERT_TRUE(budget.has_credit(start));
  budget.spend(milliseconds(8));
  // A quarter of a thread: 4 ms of debt takes 16 ms to repay.
  EXPECT_FALSE(budget.has_credit(start + milliseconds(15)));
  EXPECT_TRUE(budget.has_credit(start + milliseconds(17)));
  // An idle hour banks no more than the burst.
  const auto later = start + std::chrono::hours(1);
  ASSERT_TRUE(budget.has_credit(later));
  budget.spend(milliseconds(5));
  EXPECT_FALSE(budget.has_credit(later));
}

TEST(TimeBudget, AShareOfZeroNeverHasCredit) {
  TimeBudget budget(0.0, milliseconds(5));
  const auto start = TimeBudget::Clock::now();
  EXPECT_FALSE(budget.has_credit(start));
  EXPECT_FALSE(budget.has_credit(start + std::chrono::hours(1)));
}

}  // namespace
}  // namespace soltex::server
