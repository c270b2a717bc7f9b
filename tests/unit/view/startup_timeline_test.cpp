#include "startup_timeline.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace soltex::view {
namespace {

std::string printed(const StartupTimeline& timeline) {
  char* text = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&text, &size);
  timeline.print(out);
  std::fclose(out);
  std::string result(text, size);
  std::free(text);
  return result;
}

std::vector<double> times_of(const std::string& text) {
  std::vector<double> times;
  for (std::size_t at = text.find("timeline: "); at != std::string::npos;
       at = text.find("timeline: ", at + 1)) {
    double ms = 0.0;
    if (std::sscanf(text.c_str() + at, "timeline: %lf  +", &ms) == 1) times.push_back(ms);
  }
  return times;
}

TEST(StartupTimeline, PrintsEveryMarkInTimeOrderFromTheOrigin) {
  StartupTimeline timeline(StartupTimeline::Clock::now() - std::chrono::milliseconds(5));
  timeline.mark("first");
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&timeline, t] {
      for (int i = 0; i < 50; ++i) timeline.mark("thread " + std::to_string(t));
    });
  }
  for (std::thread& thread : threads) thread.join();
  timeline.mark("last");
  const std::string text = printed(timeline);
  EXPECT_NE(text.find("origin at"), std::string::npos) << text;
  EXPECT_LT(text.find("first"), text.find("thread 0")) << text;
  EXPECT_GT(text.find("last"), text.rfind("thread 3")) << text;
  const std::vector<double> times = times_of(text);
  ASSERT_EQ(times.size(), 202u);  // the origin line has no time of its own
  EXPECT_GE(times.front(), 5.0);  // measured from the origin given, not from construction
  for (std::size_t i = 1; i < times.size(); ++i) EXPECT_LE(times[i - 1], times[i]) << i;
}

TEST(StartupTimeline, MarksTheFetchersEventsWithTheCountSoFar) {
  StartupTimeline timeline;
  const auto on_event = fetch_marks(timeline);
  on_event(net::FetchEvent::stream_opened, 0);
  on_event(net::FetchEvent::request_written, 256);
  on_event(net::FetchEvent::batch_received, 8);
  on_event(net::FetchEvent::batch_received, 30);
  const std::string text = printed(timeline);
  EXPECT_NE(text.find("brick stream open"), std::string::npos) << text;
  EXPECT_NE(text.find("request written: 256 bricks wanted"), std::string::npos) << text;
  EXPECT_NE(text.find("batch received: 8 bricks, 8 in all"), std::string::npos) << text;
  EXPECT_NE(text.find("batch received: 30 bricks, 38 in all"), std::string::npos) << text;
}

}  // namespace
}  // namespace soltex::view
