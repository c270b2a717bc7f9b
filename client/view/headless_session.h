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

namespace soltex::view {

struct HeadlessOptions {
  std::chrono::milliseconds max_time{30000};  // give up converging after this
  bool exact = false;                         // fail unless every brick arrived
  // Called with each frame's misses before they go to the source (e.g. to record them).
  std::function<void(double seconds, const std::vector<net::BrickWant>& misses)> on_misses;
};

struct HeadlessResult {
  Image image;
  int frames = 0;
  double first_frame_ms = 0.0;
  double converged_ms = -1.0;  // -1: did not converge
  // Did not converge because bricks failed for good (refused, or corrupt after every
  // refetch): nothing was on its way any more, so it stopped before max_time.
  bool bricks_failed = false;
  double last_frame_ms = 0.0;  // raster + shade of the final frame
  FrameStats last_stats;
};

// Draws frames until nothing is missing and nothing is pending (converged), handing each
// frame's misses to the source; every frame is drawn at once from what the cache holds. Stops
// early, not converged, when the frame still misses bricks that nobody is fetching any more.
HeadlessResult render_until_converged(FrameRenderer& renderer, const PreparedScene& scene,
                                      const Camera& camera, int width, int height,
                                      net::BrickSource& source, const HeadlessOptions& options);

}  // namespace soltex::view
