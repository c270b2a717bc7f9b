#include "headless_session.h"

namespace soltex::view {

HeadlessResult render_until_converged(FrameRenderer& renderer, const PreparedScene& scene,
                                      const Camera& camera, int width, int height,
                                      net::BrickSource& source, const HeadlessOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto elapsed_ms = [&] {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  };
  HeadlessResult result;
  for (;;) {
    Frame frame = renderer.render(scene, camera, width, height);
    ++result.frames;
    if (result.frames == 1) result.first_frame_ms = elapsed_ms();
    result.last_frame_ms = frame.stats.raster_ms + frame.stats.shade_ms;
    result.last_stats = frame.stats;
    const bool complete = frame.complete();
    if (options.on_misses && !frame.misses.empty())
      options.on_misses(elapsed_ms() / 1e3, frame.misses);
    source.want(std::move(frame.misses));
    result.image = std::move(frame.image);
    if (complete && source.idle()) {
      result.converged_ms = elapsed_ms();
      return result;
    }
    if (elapsed_ms() > static_cast<double>(options.max_time.count())) return result;
    // Let some bricks arrive before drawing again; an interactive viewer would not wait.
    source.wait_idle(std::chrono::milliseconds(20));
  }
}

}  // namespace soltex::view
