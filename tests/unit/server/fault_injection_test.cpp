#include "fault_injection.h"

#include <gtest/gtest.h>

namespace soltex::server {
namespace {

TEST(FaultInjection, CorruptsExactlyEveryNthPayloadInItsLastByte) {
  FaultInjection faults(FaultConfig{0, 3});
  int corrupted = 0;
  for (int i = 0; i < 30; ++i) {
    std::string payload = "header and body";
    const bool hit = faults.corrupt_if_due(payload);
    EXPECT_EQ(hit, i % 3 == 2);
    EXPECT_EQ(payload != "header and body", hit);
    EXPECT_EQ(payload.substr(0, payload.size() - 1), "header and bod");
    corrupted += hit;
  }
  EXPECT_EQ(corrupted, 10);
  EXPECT_EQ(faults.corrupted(), 10u);
}

TEST(FaultInjection, OffByDefault) {
  FaultInjection faults(FaultConfig{});
  std::string payload = "x";
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(faults.corrupt_if_due(payload));
  EXPECT_EQ(faults.delay().count(), 0);
  EXPECT_FALSE(FaultConfig{}.any());
}

}  // namespace
}  // namespace soltex::server
