#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "soltex/net/brick_source.h"
#include "soltex/scene/scene.h"

// The paper's automatic control: measure the client machine and its link to the server,
// then choose the finest texture level, the cache budget and the frame size to match.
namespace soltex::capability {

struct Capability {
  double pixels_per_second = 0.0;  // raster + lookup + shade, all render threads
  std::size_t available_memory_mb = 0;
  double round_trip_ms = 0.0;
  double bandwidth_mb_per_s = 0.0;  // encoded brick bytes the link delivered per second
  double bytes_per_brick = 6000.0;  // measured mean encoded brick size
};

// `--capability cpu=F,mem=MB,bandwidth=MBPS`: a weaker machine, simulated. cpu scales the
// measured speed (0.25: four times slower); mem and bandwidth replace the measurements.
struct CapabilityOverride {
  std::optional<double> cpu_factor;
  std::optional<std::size_t> memory_mb;
  std::optional<double> bandwidth_mb_per_s;
};

// Throws std::invalid_argument naming the bad item and its bound.
CapabilityOverride parse_override(const std::string& text);
Capability apply(Capability measured, const CapabilityOverride& override);

// A short raster + lookup probe on this machine (a small built-in scene drawn from an
// in-process cache), and the memory the kernel reports available.
Capability measure_machine();

// Fetches 64 bricks of `texture` (a throw-away probe volume) through `source` and fills in
// bandwidth_mb_per_s and bytes_per_brick. A source that moves no bytes (in-process) leaves
// the bandwidth at 0: unlimited.
void measure_link(net::BrickSource& source, const TextureSpec& texture, Capability& capability);

struct Choice {
  int finest_level_log2 = 8;
  std::size_t cache_budget_bytes = 256u << 20;
  int width = 1280;
  int height = 720;
  std::string reason;  // one line per decision, for the log
};

struct ChoiceLimits {
  double target_frame_seconds = 0.1;  // a full frame should not take longer than this
  double fetch_seconds = 1.5;         // the finest level's surface bricks should arrive within this
  int max_level_log2 = 11;
};

// Chooses from the capability, the scene (objects' on-screen size) and the image size asked.
Choice choose(const Capability& capability, const Scene& scene, int width, int height,
              const ChoiceLimits& limits = {});

}  // namespace soltex::capability
