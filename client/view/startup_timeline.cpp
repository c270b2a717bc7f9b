#include "startup_timeline.h"

#include <spdlog/fmt/fmt.h>

#include <atomic>
#include <memory>

#include "soltex/common/process_cpu_time.h"

namespace soltex::view {

StartupTimeline::StartupTimeline(Clock::time_point origin)
    : origin_(origin), origin_cpu_ms_(process_cpu_ms()) {}

double StartupTimeline::now_ms() const {
  return std::chrono::duration<double, std::milli>(Clock::now() - origin_).count();
}

void StartupTimeline::mark(std::string what) {
  std::lock_guard lock(mutex_);  // times read under the lock keep the marks in time order
  marks_.push_back({now_ms(), process_cpu_ms() - origin_cpu_ms_, std::move(what)});
}

void StartupTimeline::print(std::FILE* out) const {
  std::lock_guard lock(mutex_);
  std::fprintf(
      out, "timeline: origin at %.6f s monotonic; ms since, +ms since the mark before, CPU ms\n",
      std::chrono::duration<double>(origin_.time_since_epoch()).count());
  double before = 0.0, cpu_before = 0.0;
  for (const Mark& m : marks_) {
    std::fprintf(out, "timeline: %8.2f  +%7.2f  cpu +%6.2f  %s\n", m.ms, m.ms - before,
                 m.cpu_ms - cpu_before, m.what.c_str());
    before = m.ms;
    cpu_before = m.cpu_ms;
  }
}

std::function<void(net::FetchEvent, std::size_t)> fetch_marks(StartupTimeline& timeline) {
  auto received = std::make_shared<std::atomic<std::size_t>>(0);
  return [&timeline, received](net::FetchEvent event, std::size_t count) {
    switch (event) {
      case net::FetchEvent::stream_opened:
        timeline.mark("brick stream open");
        break;
      case net::FetchEvent::request_written:
        timeline.mark(fmt::format("request written: {} bricks wanted", count));
        break;
      case net::FetchEvent::batch_received:
        timeline.mark(
            fmt::format("batch received: {} bricks, {} in all", count, *received += count));
        break;
    }
  };
}

}  // namespace soltex::view
