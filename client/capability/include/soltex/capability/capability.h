#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include "soltex/common/brick_codec.h"
#include "soltex/common/texture_spec.h"
#include "soltex/net/brick_source.h"
#include "soltex/scene/scene.h"

// The paper's automatic control: measure the client machine and its link to the server,
// then choose the finest texture level, the cache budget and the frame size to match.
namespace soltex::capability {

struct Capability {
  double pixels_per_second = 0.0;  // raster + lookup + shade, all render threads
  std::size_t available_memory_mb = 0;
  double round_trip_ms = 0.0;  // one GetServerInfo call
  // What a brick costs whatever its size: from asking to the first byte back (the server's
  // queue and the network's latency). Paid once per round of requests, not per brick.
  double brick_latency_ms = 0.0;
  // Encoded brick bytes per second while bricks stream, latency excluded; 0: unlimited (an
  // in-process source, or a link faster than the probe could tell).
  double bandwidth_mb_per_s = 0.0;
  double bytes_per_brick = 6000.0;  // measured mean encoded brick size
  // The codec the link warrants (codec_for_link), and the link's bandwidth measured with raw
  // bricks that cost the server next to nothing (0: not measured, or faster than the probe
  // tells). bandwidth_mb_per_s above is the scene texture's bricks, which on a fast link
  // measures the server's evaluation rather than the link.
  Codec codec = Codec::zstd;
  double raw_link_mb_per_s = 0.0;
  double zstd_decode_ns_per_byte = 0.0;  // the probe's zstd bricks, decoded here
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
// The memory alone (pixels_per_second stays 0: not measured), for a client whose frame size
// is fixed, such as headless output: the drawing probe would only decide a frame size
// (ChoiceLimits::scale_frame), and it costs about 50 ms of both cores at start-up.
Capability measure_memory();

// One burst of the link probe: bricks asked for at once, and how long until all were in.
struct LinkTiming {
  double bricks = 0.0;
  double bytes = 0.0;
  double seconds = 0.0;
};

// Tells latency from bandwidth with two bursts of different sizes, modelling a burst as
// seconds = latency + bytes / bandwidth: the larger burst's extra bytes over its extra time
// are the bandwidth, and what the small burst took beyond its bytes is the latency. A link
// 50 ms away but fast takes about 50 ms for either burst: high bandwidth, 50 ms latency.
// Sets brick_latency_ms, bandwidth_mb_per_s (0 when the larger burst was no slower: the
// link's bandwidth did not limit it) and bytes_per_brick. Leaves them when nothing moved.
void fit_link(const LinkTiming& small, const LinkTiming& large, Capability& capability);

// Where the link probe reads the time. The steady clock, unless a test drives a link of its
// own on a clock it controls (so that a burst takes exactly what the test says).
using ProbeClock = std::function<std::chrono::steady_clock::time_point()>;
inline std::chrono::steady_clock::time_point steady_now() {
  return std::chrono::steady_clock::now();
}

// Fetches a throw-away probe volume of `texture` through `source` in bursts of 1 (to open the
// stream), 8 and 64 bricks, and fits the last two (fit_link). A source that moves no bytes
// (in-process) leaves the bandwidth at 0: unlimited, and the latency at 0.
//
// With `choose_codec`, it then measures the link with raw bricks of the colour cube (cheap to
// make, so the server's evaluation does not hide the link) and sets Capability::codec and
// raw_link_mb_per_s. Leaves the source asking for zstd.
void measure_link(net::BrickSource& source, const TextureSpec& texture, Capability& capability,
                  bool choose_codec = false, const ProbeClock& clock = steady_now);

// 17^3 8-bit RGB samples and the 28-byte header: a 16^3-cell RGB brick, raw.
inline constexpr double kRawBrickBytes = 17.0 * 17.0 * 17.0 * 3.0 + 28.0;

// zstd's extra CPU over raw, soltexd's encoding and the client's decoding together, in
// multiples of the client's zstd decoding alone: about (40 + 18 - 7) / 18 us for a 14.7 kB
// marble brick (docs/PERFORMANCE.md, "Brick codec", "soltexd's encoder"). The probe times
// the decoding on this machine, under its current load, as it times the link.
inline constexpr double kZstdExtraCpuPerDecode = 2.8;

// The codec for a link of `bandwidth_mb_per_s` (0: unknown) carrying bricks that zstd
// shrinks `zstd_ratio` times, where decoding zstd takes `zstd_decode_ns_per_byte` per
// decoded byte: raw when the bytes zstd saves take less time on the link than compressing
// and decompressing them take CPU (loopback, a fast LAN), else zstd. lz4 sits between and is
// left to --codec.
Codec codec_for_link(double bandwidth_mb_per_s, double zstd_ratio, double zstd_decode_ns_per_byte);

// The capability sets where a client starts, not where it ends: every client prepares its
// textures at the same finest level (the level the picture needs, as far as the cache holds
// it), so that all of them converge to the same picture; a weak link or machine starts at a
// coarser cap (start_level_log2), fetches no finer while it is busy, and refines to the
// finest level once idle (client/view/level_cap.h).
struct Choice {
  int finest_level_log2 = 8;  // the textures' finest level: where a client may end
  // <= finest_level_log2: the cap it starts from; it refines from there while the cache holds
  // what the next level needs (a frame's misses say), so a cache too small for the finest
  // level stops it where the cache is full, not at a level guessed before the first frame.
  int start_level_log2 = 8;
  std::size_t cache_budget_bytes = 256u << 20;
  int width = 1280;
  int height = 720;
  std::string reason;  // one line per decision, for the log
};

struct ChoiceLimits {
  double target_frame_seconds = 0.1;  // a full frame should not take longer than this
  double fetch_seconds = 1.5;         // the start level's surface bricks should arrive within this
  // The finest level a picture may refine to: the scene's objects (a texel per pixel where
  // they come nearest) and the cache budget choose below it. A material's own volume, or
  // --finest-level, sets a level outright.
  int max_level_log2 = SpecLimits::kMaxFinestLevelLog2;
  // --finest-level: the finest level set outright (0: chosen from the scene); the start is
  // still chosen below it, from the cache budget and the link.
  int finest_level_log2 = 0;
  std::size_t in_flight_bricks = 256;  // bricks a client asks for per round (FetcherOptions)
  // Shrink the frame to what the machine draws in target_frame_seconds (a window); false:
  // keep the size asked for (headless output is the size the scene or command line asks).
  bool scale_frame = true;
  // Texels a frame pixel reads for each one a lookup at its level reads: antialias^2 sub-pixels
  // each, and 4 per level a negative level bias goes finer.
  double texels_per_pixel = 1.0;
};

// Chooses from the capability, the scene (objects' on-screen size) and the image size asked.
// finest_level_log2 depends on the scene, the frame and the memory, never on the link.
Choice choose(const Capability& capability, const Scene& scene, int width, int height,
              const ChoiceLimits& limits = {});

}  // namespace soltex::capability
