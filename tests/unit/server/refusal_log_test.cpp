#include "refusal_log.h"

#include <gtest/gtest.h>

#include <vector>

namespace soltex::server {
namespace {

using std::chrono::milliseconds;

TEST(RefusalLog, OneLinePerClientPerSecondWithTheCountLeftOut) {
  std::vector<std::string> lines;
  RefusalLog log([&](const std::string& line) { lines.push_back(line); });
  const auto t0 = RefusalLog::Clock::time_point{} + std::chrono::hours(1);
  for (int i = 0; i < 100; ++i) log.refused("10.0.0.1", "refused A", t0 + milliseconds(i));
  log.refused("10.0.0.2", "refused B", t0 + milliseconds(50));  // another client: its own line
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "refused A");
  EXPECT_EQ(lines[1], "refused B");
  EXPECT_EQ(log.suppressed(), 99u);

  log.refused("10.0.0.1", "refused A again", t0 + milliseconds(1000));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[2],
            "refused A again (99 more refusals of 10.0.0.1 not logged since its last line)");
  log.refused("10.0.0.1", "refused A later", t0 + milliseconds(2500));
  EXPECT_EQ(lines.back(), "refused A later");  // nothing left out since
}

TEST(RefusalLog, ManyClientsStayBounded) {
  std::size_t lines = 0;
  RefusalLog log([&](const std::string&) { ++lines; });
  const auto t0 = RefusalLog::Clock::time_point{} + std::chrono::hours(1);
  // 100,000 distinct addresses within one second: the first 4096 get a line each, the rest
  // share one entry.
  for (int i = 0; i < 100000; ++i) log.refused("client" + std::to_string(i), "x", t0);
  EXPECT_EQ(lines, 4096u + 1u);
  // A second later the quiet ones are forgotten and new clients get their lines again.
  log.refused("late", "x", t0 + std::chrono::seconds(2));
  EXPECT_EQ(lines, 4096u + 2u);
}

}  // namespace
}  // namespace soltex::server
