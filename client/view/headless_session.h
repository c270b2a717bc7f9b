#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "soltex/common/texture_sampler.h"
#include "soltex/net/brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "startup_timeline.h"

namespace soltex::view {

struct HeadlessOptions {
  std::chrono::milliseconds max_time{30000};  // give up converging after this
  // Converge first with no texture finer than 2^start_level_log2 samples per axis (the
  // capability's start), then refine to the prepared levels as far as `cache` holds them
  // (level_cap.h). 0, or no cache: draw at the prepared levels from the start.
  int start_level_log2 = 0;
  const BrickCache* cache = nullptr;
  // Draw the first frame for its misses alone (RenderOptions::misses_only): it asks for the
  // same bricks as a shaded frame (the same levels and lookups) without reading a sample,
  // lighting or evaluating any texture per pixel. Its picture is never the output: should it miss
  // nothing, the next frame, drawn at once, is shaded.
  bool first_frame_for_misses = true;
  // Ask for each raster tile's misses as soon as the tile is shaded (BrickSource::
  // want_early), so that the server makes bricks while the frame is still being drawn.
  bool request_while_drawing = true;
  // Called with each frame's misses before they go to the source (e.g. to record them).
  std::function<void(double seconds, const std::vector<net::BrickWant>& misses)> on_misses;
  // Marks each frame's start and end and each wait for bricks (null: none).
  StartupTimeline* timeline = nullptr;
};

struct HeadlessResult {
  Image image;
  int frames = 0;
  double first_frame_ms = 0.0;
  double converged_ms = -1.0;  // -1: did not converge
  // With a start level: when the picture at the start level converged (-1: it did not), and
  // the finest resolution (log2) the run refined to; below the prepared levels when the
  // cache budget stopped it there.
  double start_converged_ms = -1.0;
  int start_level_log2 = 0;
  int refined_level_log2 = 0;
  // Did not converge because bricks failed for good (refused, or corrupt after every
  // refetch): nothing was on its way any more, so it stopped before max_time.
  bool bricks_failed = false;
  double last_frame_ms = 0.0;  // raster + shade of the final frame
  // Where the time to converged went, wall: drawing frames, and waiting for bricks with
  // nothing new to draw (the server's evaluation and the link, less what the frames hid).
  double drawing_ms = 0.0;
  double waiting_ms = 0.0;
  double cpu_ms = 0.0;  // this process's CPU time (all threads) until converged or given up
  FrameStats last_stats;
};

// Draws frames until nothing is missing and nothing is pending (converged), handing each
// frame's misses to the source; every frame is drawn at once from what the cache holds. Stops
// early, not converged, when the frame still misses bricks that nobody is fetching any more.
// With a start level it converges at that cap first, then lifts the cap in one step (the
// output is the final picture only, so the levels in between would be wasted fetches). A
// texture the source refuses meanwhile is evaluated per pixel from the next frame on.
HeadlessResult render_until_converged(FrameRenderer& renderer, PreparedScene& scene,
                                      const Camera& camera, int width, int height,
                                      net::BrickSource& source, const HeadlessOptions& options);

}  // namespace soltex::view
