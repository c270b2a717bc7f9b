#include "window_title.h"

#include <cstdio>

namespace soltex::view {

std::string window_title(const ViewerStatus& status) {
  char frames[64];
  if (status.idle) {
    std::snprintf(frames, sizeof frames, "idle");
  } else {
    std::snprintf(frames, sizeof frames, "%.1f fps (%.1f ms)", status.frames_per_second,
                  status.frame_ms);
  }
  char title[256];
  std::snprintf(title, sizeof title,
                "soltex-view | %s | hit %.1f %% | %zu bricks pending | %.2f MB | bias %+.2f%s | "
                "%s%s",
                frames, 100.0 * status.cache_hit_rate, status.pending_bricks,
                static_cast<double>(status.bytes_received) / 1e6, status.level_bias,
                status.adaptive_bias ? " auto" : "", status.filter,
                status.false_colour_levels ? " | false-colour levels" : "");
  return title;
}

}  // namespace soltex::view
