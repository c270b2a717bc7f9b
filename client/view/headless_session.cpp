#include "headless_session.h"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <climits>

#include "level_cap.h"
#include "refused_textures.h"
#include "soltex/common/process_cpu_time.h"

namespace soltex::view {
namespace {

using Clock = std::chrono::steady_clock;

// While a frame is drawn: hands each raster tile's misses to `source` as the cap (if any)
// lets them be fetched, and holds the bricks that arrive meanwhile out of the cache until the
// frame ends (an insertion makes every lookup the frame found missing look again); for as
// long as it lives.
class EarlyRequests {
 public:
  EarlyRequests(FrameRenderer& renderer, net::BrickSource& source, const LevelCap* cap,
                const BrickCache* cache, bool on)
      : renderer_(renderer), source_(on ? &source : nullptr) {
    if (!on) return;
    source.hold_arrivals(true);
    renderer.set_on_tile_misses([&source, cap, cache](std::vector<net::BrickWant> wants) {
      if (cap != nullptr && cache != nullptr) wants = not_resident(cap->apply(wants), *cache);
      if (!wants.empty()) source.want_early(std::move(wants));
    });
  }
  ~EarlyRequests() {
    if (source_ == nullptr) return;
    renderer_.set_on_tile_misses(nullptr);
    source_->hold_arrivals(false);
  }
  EarlyRequests(const EarlyRequests&) = delete;
  EarlyRequests& operator=(const EarlyRequests&) = delete;

 private:
  FrameRenderer& renderer_;
  net::BrickSource* source_;
};

// One frame, counted and timed into `result`; nothing but its misses when it is drawn only
// for them.
Frame draw(FrameRenderer& renderer, const PreparedScene& scene, const Camera& camera, int width,
           int height, bool for_misses, HeadlessResult& result, StartupTimeline* timeline) {
  mark_on(timeline, fmt::format("frame {} starts{}", result.frames + 1,
                                for_misses ? " (for its misses only)" : ""));
  const auto start = std::chrono::steady_clock::now();
  if (for_misses) renderer.set_misses_only(true);
  Frame frame = renderer.render(scene, camera, width, height);
  if (for_misses) renderer.set_misses_only(false);
  result.drawing_ms +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ++result.frames;
  result.last_frame_ms = frame.stats.raster_ms + frame.stats.shade_ms;
  result.last_stats = frame.stats;
  mark_on(timeline,
          fmt::format("frame {} ends: {} misses, {} pixels from a coarser level (raster {:.2f} ms, "
                      "shading {:.2f} ms)",
                      result.frames, frame.misses.size(), frame.stats.fallback_pixels,
                      frame.stats.raster_ms, frame.stats.shade_ms));
  return frame;
}

// The cap a run starts under, null where nothing is capped; the levels go into `result`.
LevelCap* start_cap(LevelCap& levels, const HeadlessOptions& options, HeadlessResult& result) {
  result.refined_level_log2 = levels.finest_log2();
  levels.set_cap_log2(options.start_level_log2);
  LevelCap* cap = options.start_level_log2 > 0 && options.cache != nullptr && levels.active()
                      ? &levels
                      : nullptr;
  result.start_level_log2 = cap != nullptr ? cap->cap_log2() : result.refined_level_log2;
  return cap;
}

// Idle at `cap` with nothing missing: lifts it as far as the cache holds what the finer levels
// need (to null once nothing is capped). False where the budget keeps it where it is: the run
// has converged as it is.
bool lift_cap(LevelCap*& cap, const Frame& frame, const BrickCache& cache, HeadlessResult& result) {
  const int next = next_cap(*cap, frame.misses, cache, INT_MAX);
  if (next == cap->cap_log2()) {
    result.refined_level_log2 = next;
    return false;
  }
  cap->set_cap_log2(next);
  if (!cap->active()) cap = nullptr;
  return true;
}

// Waits until nothing is pending or `deadline` passes. The output is the converged image, so a
// headless run draws again only when everything asked for is in (or the time is up): frames in
// between only take CPU from decoding and, where soltexd shares the machine, from evaluation.
// The interactive viewer draws every frame.
void wait_for_bricks(net::BrickSource& source, Clock::time_point deadline, HeadlessResult& result,
                     StartupTimeline* timeline) {
  const auto wait_start = Clock::now();
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - wait_start);
  mark_on(timeline, "waits for bricks");
  source.wait_idle(std::max(left, std::chrono::milliseconds(1)));
  mark_on(timeline, "nothing pending any more");
  result.waiting_ms += std::chrono::duration<double, std::milli>(Clock::now() - wait_start).count();
}

HeadlessResult converge(FrameRenderer& renderer, PreparedScene& scene, const Camera& camera,
                        int width, int height, net::BrickSource& source,
                        const HeadlessOptions& options) {
  const auto start = Clock::now();
  const auto elapsed_ms = [&] {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  };
  HeadlessResult result;
  LevelCap levels(scene);
  // Null once nothing is capped: from then on the run is a run without a start level.
  LevelCap* cap = start_cap(levels, options, result);
  uint64_t received = source.stats().received;
  int stalled = 0;  // frames in a row that missed bricks while nothing was on its way
  // A frame drawn only to find its misses (RenderOptions::misses_only: rasterized, each pixel's
  // bricks looked up, nothing shaded); a run that draws false colour anyway needs no such
  // frame.
  bool for_misses = options.first_frame_for_misses && !renderer.options().false_colour_levels;
  for (;;) {
    adopt_refused_textures(scene, source);
    const uint64_t received_before_frame = source.stats().received;
    Frame frame = [&] {
      const EarlyRequests early(renderer, source, cap, options.cache,
                                options.request_while_drawing);
      return draw(renderer, scene, camera, width, height, for_misses, result, options.timeline);
    }();
    if (result.frames == 1) result.first_frame_ms = elapsed_ms();
    const FrameNeeds needs =
        needs_of(frame, cap, options.cache, source.stats().received != received_before_frame);
    if (options.on_misses && !needs.wants.empty())
      options.on_misses(elapsed_ms() / 1e3, needs.wants);
    source.want(needs.wants);
    if (for_misses) {
      for_misses = false;
      // Nothing to fetch: the shaded picture is one frame away, drawn now.
      if (needs.wants.empty()) continue;
    } else {
      result.image = std::move(frame.image);
    }
    if (needs.complete && source.idle()) {
      if (cap == nullptr) {
        result.converged_ms = elapsed_ms();
        if (result.start_converged_ms < 0.0) result.start_converged_ms = result.converged_ms;
        return result;
      }
      if (result.start_converged_ms < 0.0) result.start_converged_ms = elapsed_ms();
      if (!lift_cap(cap, frame, *options.cache, result)) {
        result.converged_ms = elapsed_ms();
        return result;
      }
      received = source.stats().received;
      stalled = 0;
      continue;  // draw at once: the new cap's misses go out with the next frame
    }
    if (elapsed_ms() > static_cast<double>(options.max_time.count())) {
      // Out of time after a frame drawn only for its misses: the output is the scene as the
      // cache holds it, shaded.
      if (result.image.rgb.empty()) {
        result.image =
            draw(renderer, scene, camera, width, height, false, result, options.timeline).image;
      }
      return result;
    }
    // Bricks missing, none on its way and none arrived since the last frame: they failed (a
    // failed brick is not asked for again), and drawing on would change nothing. Two frames
    // in a row, because bricks that land during a frame leave it incomplete once.
    const uint64_t now_received = source.stats().received;
    stalled = !needs.complete && source.idle() && now_received == received ? stalled + 1 : 0;
    received = now_received;
    if (stalled >= 2) {
      result.bricks_failed = true;
      return result;
    }
    wait_for_bricks(source, start + options.max_time, result, options.timeline);
  }
}

}  // namespace

HeadlessResult render_until_converged(FrameRenderer& renderer, PreparedScene& scene,
                                      const Camera& camera, int width, int height,
                                      net::BrickSource& source, const HeadlessOptions& options) {
  const double cpu_start = process_cpu_ms();
  HeadlessResult result = converge(renderer, scene, camera, width, height, source, options);
  result.cpu_ms = process_cpu_ms() - cpu_start;
  return result;
}

}  // namespace soltex::view
