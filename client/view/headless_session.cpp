#include "headless_session.h"

#include <algorithm>

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
  uint64_t received = source.stats().received;
  int stalled = 0;  // frames in a row that missed bricks while nothing was on its way
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
    // Bricks missing, none on its way and none arrived since the last frame: they failed (a
    // failed brick is not asked for again), and drawing on would change nothing. Two frames
    // in a row, because bricks that land during a frame leave it incomplete once.
    const uint64_t now_received = source.stats().received;
    stalled = !complete && source.idle() && now_received == received ? stalled + 1 : 0;
    received = now_received;
    if (stalled >= 2) {
      result.bricks_failed = true;
      return result;
    }
    // The output is the converged image, so draw again only when everything asked for is in
    // (or the time is up): frames in between only take CPU from decoding and, where soltexd
    // shares the machine, from evaluation. The interactive viewer draws every frame.
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        start + options.max_time - Clock::now());
    source.wait_idle(std::max(left, std::chrono::milliseconds(1)));
  }
}

}  // namespace soltex::view
