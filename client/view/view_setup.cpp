#include "view_setup.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>

#include "soltex/net/local_brick_source.h"
#include "soltex/net/loopback_address.h"

namespace soltex::view {
namespace {

// How the client reaches its bricks, as far as choosing a codec and a start goes.
enum class Link { probed, loopback, unprobed };

// The codec bricks travel in: --codec's, else the one the link warrants (the probe's, a
// simulated --capability bandwidth's, raw over loopback, or zstd, the default, over a link
// that was not probed because the scene has nothing to fetch), logged with why.
Codec choose_codec(std::optional<Codec> forced, const capability::Capability& measured,
                   const capability::CapabilityOverride& override, Link link_kind) {
  if (forced) {
    spdlog::info("codec: {} (--codec)", codec_name(*forced));
    return *forced;
  }
  if (link_kind == Link::loopback) {
    spdlog::info(
        "codec: {}: loopback, where encoding and decoding cost more than the bytes they save "
        "(--codec overrides; a port forwarded to another machine wants --codec zstd)",
        codec_name(measured.codec));
    return measured.codec;
  }
  if (link_kind == Link::unprobed) {
    spdlog::info("codec: {}: the link was not probed (the scene has no objects)",
                 codec_name(measured.codec));
    return measured.codec;
  }
  const double zstd_ratio = capability::kRawBrickBytes / measured.bytes_per_brick;
  Codec codec = measured.codec;
  std::string link = measured.raw_link_mb_per_s > 0.0
                         ? fmt::format("{:.0f} MB/s", measured.raw_link_mb_per_s)
                         : std::string("more MB/s than the probe can tell");
  if (override.bandwidth_mb_per_s) {
    codec = capability::codec_for_link(*override.bandwidth_mb_per_s, zstd_ratio,
                                       measured.zstd_decode_ns_per_byte);
    link = fmt::format("{} MB/s (simulated)", *override.bandwidth_mb_per_s);
  }
  spdlog::info(
      "codec: {}: the link carries raw bricks at {}, zstd shrinks them {:.1f} times and "
      "decodes at {:.2f} ns per byte (--codec overrides)",
      codec_name(codec), link, zstd_ratio, measured.zstd_decode_ns_per_byte);
  return codec;
}

// The server's first answer, within 5 s and within a headless run's --max-time-s.
double round_trip_ms(net::BrickFetcher& fetcher, const ViewOptions& options) {
  const auto timeout = options.server_wait(std::chrono::seconds(5));
  return static_cast<double>(fetcher.measure_round_trip(timeout).count()) / 1e3;
}

// Over loopback the link is this machine's memory: the probe would find no latency worth a
// coarser start and raw bricks cheapest (docs/PROTOCOL.md, section 6), after costing the start
// about 30 ms and soltexd the CPU of its probe bricks. An in-process source moves no bytes, so
// a probe of it measures nothing. A simulated bandwidth needs the probe's zstd figures to
// choose a codec.
Link link_of(const ViewOptions& options, const Scene& scene,
             const capability::CapabilityOverride& override) {
  if (scene.objects.empty()) return Link::unprobed;
  const bool loopback = net::is_loopback_address(options.server);
  return loopback && !override.bandwidth_mb_per_s.has_value() ? Link::loopback : Link::probed;
}

// The link probe, on its own cache and connection: its bricks are no part of the picture (nor
// of the timeline's counts of the picture's bricks).
void probe_link(const ViewOptions& options, const Scene& scene, net::FetcherOptions fetcher_options,
                capability::Capability& measured, StartupTimeline* timeline) {
  fetcher_options.on_event = nullptr;
  BrickCache probe_cache(256u << 20);
  net::BrickFetcher probe(options.server, probe_cache, fetcher_options);
  measured.round_trip_ms = round_trip_ms(probe, options);
  mark_on(timeline,
          fmt::format("connected: GetServerInfo answered in {:.2f} ms", measured.round_trip_ms));
  capability::measure_link(probe, scene.objects.front().material.texture, measured,
                           !options.forced_codec().has_value());
  mark_on(timeline, "link probe done");
}

capability::Choice choose(const ViewOptions& options, const Scene& scene,
                          const capability::Capability& effective) {
  // Headless output, and a window given a size, keep the size asked for exactly; a window
  // showing the scene's size shrinks it to what this machine draws in time.
  capability::ChoiceLimits limits;
  limits.scale_frame = !options.headless && options.width == 0 && options.height == 0;
  limits.finest_level_log2 = options.finest_level;
  limits.texels_per_pixel = static_cast<double>(options.antialias) * options.antialias *
                            std::pow(4.0, std::max(0.0, -options.level_bias));
  // A headless run shows nothing before it converges: a coarse start only guards its time
  // limit, so the start level's bricks may take half of it (a window starts within 1.5 s).
  if (options.headless) {
    limits.fetch_seconds = std::max(limits.fetch_seconds, options.max_seconds / 2.0);
  }
  capability::Choice choice =
      capability::choose(effective, scene, options.width > 0 ? options.width : scene.image.width,
                         options.height > 0 ? options.height : scene.image.height, limits);
  return choice;
}

void log_setup(const ViewOptions& options, const ViewSetup& setup, Link link_kind) {
  const capability::Capability& effective = setup.effective;
  const std::string link =
      link_kind == Link::probed || options.local
          ? fmt::format("brick latency {:.1f} ms, link {:.1f} MB/s", effective.brick_latency_ms,
                        effective.bandwidth_mb_per_s)
          : std::string(link_kind == Link::loopback ? "loopback link (not probed)"
                                                    : "link not probed");
  spdlog::info(
      "capability: {}, {} MiB available, round trip {:.2f} ms, {}{}",
      effective.pixels_per_second > 0.0
          ? fmt::format("{:.1f} Mpixel/s", effective.pixels_per_second / 1e6)
          : std::string("drawing speed not measured (the frame keeps its size)"),
      effective.available_memory_mb, setup.measured.round_trip_ms, link,
      options.capability_text.empty() ? "" : " (simulated: " + options.capability_text + ")");
  const std::string& reason = setup.choice.reason;
  for (std::size_t begin = 0; begin < reason.size();) {
    const std::size_t end = reason.find('\n', begin);
    spdlog::info("choice: {}", reason.substr(begin, end - begin));
    begin = end == std::string::npos ? reason.size() : end + 1;
  }
}

}  // namespace

ViewSetup set_up_view(const ViewOptions& options, const Scene& scene,
                      net::FetcherOptions fetcher_options, StartupTimeline* timeline) {
  capability::CapabilityOverride override;
  if (!options.capability_text.empty()) {
    override = capability::parse_override(options.capability_text);
  }
  ViewSetup setup;
  // Headless output keeps the size asked for, so nothing needs this machine's drawing speed.
  setup.measured = options.headless ? capability::measure_memory() : capability::measure_machine();
  mark_on(timeline, options.headless ? "memory measured" : "machine probe done");
  const Link link_kind = options.local ? Link::unprobed : link_of(options, scene, override);
  if (link_kind == Link::probed) {
    probe_link(options, scene, fetcher_options, setup.measured, timeline);
  } else if (link_kind == Link::loopback) {
    setup.measured.codec = Codec::raw;
  }
  setup.effective = capability::apply(setup.measured, override);
  setup.choice = choose(options, scene, setup.effective);
  setup.cache = std::make_unique<BrickCache>(setup.choice.cache_budget_bytes);
  if (options.local) {
    setup.source = std::make_unique<net::LocalBrickSource>(*setup.cache);
  } else {
    fetcher_options.codec =
        choose_codec(options.forced_codec(), setup.measured, override, link_kind);
    auto fetcher =
        std::make_unique<net::BrickFetcher>(options.server, *setup.cache, fetcher_options);
    if (link_kind != Link::probed) {
      setup.measured.round_trip_ms = round_trip_ms(*fetcher, options);
      mark_on(timeline, fmt::format("connected: GetServerInfo answered in {:.2f} ms (no link "
                                    "probe)",
                                    setup.measured.round_trip_ms));
    }
    setup.source = std::move(fetcher);
  }
  log_setup(options, setup, link_kind);
  return setup;
}

}  // namespace soltex::view
