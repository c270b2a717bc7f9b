#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace soltex::view {

// What the viewer reports about itself. There is no font library, so it goes into the
// window's title bar.
struct ViewerStatus {
  double frames_per_second = 0.0;
  double frame_ms = 0.0;  // the last frame drawn, render and present
  double cache_hit_rate = 0.0;
  std::size_t pending_bricks = 0;  // waiting or in flight
  uint64_t bytes_received = 0;     // encoded brick bytes (0 for an in-process source)
  double level_bias = 0.0;
  bool adaptive_bias = true;
  const char* filter = "";
  bool false_colour_levels = false;
  bool idle = false;  // nothing to refine and nothing changing: no frames are drawn
};

// e.g. "soltex-view | 24.1 fps (38.2 ms) | hit 97.3 % | 12 bricks pending | 3.40 MB |
// bias +0.50 auto | trilinear"
std::string window_title(const ViewerStatus& status);

}  // namespace soltex::view
