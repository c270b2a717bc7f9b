// soltex-view: objects carved out of procedural solid textures, drawn in software from a local
// sparse brick cache that fills from soltexd (or from an in-process evaluator with --local).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include "headless_session.h"
#include "request_log.h"
#include "soltex/cli/tool_cli.h"
#include "startup_timeline.h"
#ifdef SOLTEX_HAVE_SDL2
#include "viewer_window.h"
#endif
#include "soltex/capability/capability.h"
#include "soltex/net/brick_fetcher.h"
#include "soltex/net/channel_security_options.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/net/loopback_address.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/scene/default_scene.h"
#include "soltex/scene/scene_error.h"
#include "soltex/scene/scene_loader.h"

namespace {

using namespace soltex;

// soltex-view's exit codes: the table every tool shares (README.md, "Exit codes").
// 0: the picture converged (a window: closed normally); 1: a runtime failure (the server, a
// file, the network); 2: a bad command line or scene, or no display for a window; 3: written
// but not converged, as --max-time-s ran out or bricks failed for good (refused, or corrupt
// each time).
constexpr int kExitConverged = cli::kExitOk;
constexpr int kExitFailure = cli::kExitFailure;
constexpr int kExitBadInput = cli::kExitUsage;
constexpr int kExitNotConverged = cli::kExitNotConverged;

SampleFilter filter_from(const std::string& name) {
  if (name == "nearest") return SampleFilter::nearest;
  if (name == "quadrilinear") return SampleFilter::quadrilinear;
  return SampleFilter::trilinear;
}

TextureAccess access_from(const std::string& name) {
  if (name == "cache") return TextureAccess::cached;
  if (name == "evaluate") return TextureAccess::evaluated;
  return TextureAccess::automatic;
}

std::optional<Codec> codec_from(const std::string& name) {
  if (name == "zstd") return Codec::zstd;
  if (name == "lz4") return Codec::lz4;
  if (name == "raw") return Codec::raw;
  return std::nullopt;  // auto: the link probe's choice
}

MipMode mip_from(const std::string& name) {
  if (name == "point") return MipMode::point;
  if (name == "supersampled") return MipMode::supersampled;
  return MipMode::band_limited;
}

// The codec bricks travel in: --codec's, else the one the link warrants (the probe's, a
// simulated --capability bandwidth's, or raw over an unprobed loopback link), logged with why.
Codec choose_codec(std::optional<Codec> forced, const capability::Capability& measured,
                   const capability::CapabilityOverride& override, bool probed) {
  if (forced) {
    spdlog::info("codec: {} (--codec)", codec_name(*forced));
    return *forced;
  }
  if (!probed) {
    spdlog::info(
        "codec: {}: loopback, where encoding and decoding cost more than the bytes they save "
        "(--codec overrides; a port forwarded to another machine wants --codec zstd)",
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

#ifdef SOLTEX_HAVE_SDL2
// The interactive window; with max_frames it closes by itself (screenshots, tests).
int run_window(const Scene& scene, const TextureResolution& resolution, BrickCache& cache,
               net::BrickSource& source, const RenderOptions& render_options,
               const capability::Choice& choice, int max_frames,
               const std::filesystem::path& screenshot) {
  view::ViewerSettings settings;
  settings.width = choice.width;
  settings.height = choice.height;
  settings.start_level_log2 = choice.start_level_log2;
  settings.max_frames = max_frames;
  settings.screenshot = screenshot;
  std::unique_ptr<view::ViewerWindow> window;
  try {
    window = std::make_unique<view::ViewerWindow>(scene, resolution, cache, source, render_options,
                                                  settings);
  } catch (const view::WindowUnavailable& e) {
    std::fprintf(stderr, "soltex-view: %s; use --headless --out IMAGE.png without a display\n",
                 e.what());
    return kExitBadInput;
  }
  spdlog::info(
      "window {}x{}: left drag orbits, wheel zooms, 1..9/Tab switch textures (0: the scene's), "
      "Up/Down move the clip plane, L levels, F filter, A adaptive bias, R reset, Esc/Q quit",
      choice.width, choice.height);
  const view::ViewerResult result = window->run();
  window.reset();
  const net::SourceStats fetched = source.stats();
  const BrickCacheStats cached = cache.stats();
  std::printf("frames:     %d; first frame after %.1f ms\n", result.frames, result.first_frame_ms);
  std::printf("bricks:     %llu received, %.2f MB, %zu still pending\n",
              static_cast<unsigned long long>(fetched.received), fetched.bytes / 1e6,
              fetched.waiting + fetched.in_flight);
  std::printf("cache:      %llu bricks, %.1f MB resident, hit rate %.2f %%\n",
              static_cast<unsigned long long>(cached.resident_bricks), cached.resident_bytes / 1e6,
              100.0 * cached.hit_rate());
  if (!screenshot.empty()) std::printf("wrote:      %s\n", screenshot.c_str());
  return kExitConverged;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  view::StartupTimeline timeline;  // the program's start: the first thing it does
  CLI::App app{"soltex-view: software-rendered solid textures from a sparse brick cache"};
  std::string server;
  bool local = false;
  std::filesystem::path scene_path;
  std::filesystem::path out = "soltex-view.png";
  bool headless = false;
  bool exact = false;
  bool reference = false;
  int supersample = 1;
  std::string capability_text;
  std::string filter_name = "trilinear";
  std::string mip_name = "band-limited";
  std::string access_name = "auto";
  std::string codec_name = "auto";
  int antialias = 1;
  int edge_antialias = 0;
  double level_bias = 0.0;
  bool false_colour = false;
  double max_seconds = 30.0;
  int threads = 0;
  int finest_level = 0;
  int brick_size = 16;
  int width = 0, height = 0;
  std::filesystem::path record_path;
  bool print_timeline = false;
  std::string log_level = "info";
  int window_frames = 0;
  std::filesystem::path screenshot;
  cli::add_common_options(app, "soltex-view", log_level);
  app.add_option("--server", server, "soltexd address HOST:PORT");
  app.add_flag("--local", local, "evaluate bricks in this process instead of fetching them");
  app.add_option("--scene", scene_path, "scene file (JSON); default: the built-in scene")
      ->check(CLI::ExistingFile);
  app.add_option("--out", out, "PNG to write (headless)")->capture_default_str();
  app.add_flag("--headless", headless, "render until converged, write --out, print statistics");
  app.add_flag("--exact", exact,
               "wait for every brick, so the image depends on the settings alone (every "
               "headless run now does: one that does not converge exits 3)");
  app.add_flag("--reference", reference,
               "also render by evaluating the texture per pixel; print PSNR and speed ratio");
  app.add_option("--supersample", supersample, "reference sub-pixels per axis")
      ->check(CLI::Range(1, 8))
      ->capture_default_str();
  app.add_option("--capability", capability_text,
                 "simulate a weaker machine: cpu=FACTOR,mem=MB,bandwidth=MBPS");
  app.add_option("--filter", filter_name, "texture filter")
      ->check(CLI::IsMember({"nearest", "trilinear", "quadrilinear"}))
      ->capture_default_str();
  app.add_option("--mip", mip_name, "MIP construction")
      ->check(CLI::IsMember({"point", "band-limited", "supersampled"}))
      ->capture_default_str();
  app.add_option("--texture-access", access_name,
                 "how pixels read textures: auto evaluates the cheap analytic patterns (stripes, "
                 "checkers, rings, colour cube) per pixel and caches the rest; cache or evaluate "
                 "force one way for every texture")
      ->check(CLI::IsMember({"auto", "cache", "evaluate"}))
      ->capture_default_str();
  app.add_option("--antialias", antialias,
                 "sub-pixels per axis for silhouettes and clip edges (1: off); costs about "
                 "antialias^2 times the frame")
      ->check(CLI::Range(1, 4))
      ->capture_default_str();
  app.add_option("--edge-antialias", edge_antialias,
                 "coverage samples per axis at edge pixels only (silhouettes, object and clip "
                 "edges, depth breaks), each surface there shaded once (0: off; 2 to 8)")
      ->check(CLI::IsMember({0, 2, 3, 4, 5, 6, 7, 8}))
      ->capture_default_str();
  app.add_option("--level-bias", level_bias, "added to every pixel's level (negative: finer)")
      ->check(CLI::Range(-8.0, 8.0));
  app.add_flag("--false-colour", false_colour, "show each pixel's level in false colour");
  app.add_option("--max-time-s,--max-seconds", max_seconds,
                 "give up converging after this many seconds (exit 3; --max-seconds: old name)")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  app.add_option("--threads", threads, "render threads (0: one per core)")
      ->check(CLI::Range(0, 256));
  app.add_option("--finest-level", finest_level,
                 "finest texture level log2 the picture refines to (0: from the scene's size on "
                 "screen and this machine's memory; the link only sets where it starts)")
      ->check(CLI::Range(0, 14));
  app.add_option("--brick-size", brick_size,
                 "cells per brick side: 16 draws warm frames faster, 8 fetches fewer bytes and "
                 "converges sooner from a cold start (docs/PERFORMANCE.md)")
      ->check(CLI::IsMember({8, 16}))
      ->capture_default_str();
  app.add_option("--width", width,
                 "frame width (0: the scene's; a window scales the scene's to this machine)")
      ->check(CLI::Range(0, 16384));
  app.add_option("--height", height,
                 "frame height (0: the scene's; a window scales the scene's to this machine)")
      ->check(CLI::Range(0, 16384));
  auto* headless_flag = app.get_option("--headless");
  app.add_option("--frames", window_frames,
                 "window: close after this many frames (0: when closed by the user)")
      ->check(CLI::Range(0, 1000000))
      ->excludes(headless_flag);
  app.add_option("--screenshot", screenshot, "window: write the last frame shown to this PNG")
      ->excludes(headless_flag);
  app.add_option("--codec", codec_name,
                 "how bricks travel: auto takes whichever of zstd and raw brought the link "
                 "probe's bricks faster (raw where encoding costs more than the bytes, as over "
                 "loopback); zstd, lz4 or raw force one")
      ->check(CLI::IsMember({"auto", "zstd", "lz4", "raw"}))
      ->capture_default_str();
  app.add_option("--record", record_path,
                 "write every brick request to FILE (soltex-load --mix replay plays it back)");
  app.add_flag("--timeline", print_timeline,
               "headless: print when each step of the start happened (probes, frames, requests, "
               "each batch of bricks received), in ms since the program started");
  net::ChannelSecurityOptions security_options;
  net::add_channel_security_options(app, security_options);
  if (const auto exit_code = cli::parse(app, "soltex-view", argc, argv)) return *exit_code;
  cli::start_logging("soltex-view", log_level);
  if (!local && server.empty()) {
    std::fprintf(stderr, "soltex-view: give --server HOST:PORT, or --local to run without one\n");
    return kExitBadInput;
  }
#ifndef SOLTEX_HAVE_SDL2
  if (!headless) {
    std::fprintf(stderr,
                 "soltex-view: this build has no window support; use --headless --out IMAGE.png\n");
    return kExitBadInput;
  }
#endif

  try {
    net::FetcherOptions fetcher_options;
    fetcher_options.security = net::finish_channel_security(security_options);
    // Null marks nothing: the timeline costs only where it is printed.
    view::StartupTimeline* const marks = print_timeline && headless ? &timeline : nullptr;
    const auto mark = [&](std::string what) {
      if (marks != nullptr) marks->mark(std::move(what));
    };
    if (marks != nullptr) fetcher_options.on_event = fetch_marks(*marks);
    mark("command line read");
    const Scene scene = scene_path.empty() ? default_scene() : load_scene(scene_path);
    capability::CapabilityOverride override;
    if (!capability_text.empty()) override = capability::parse_override(capability_text);

    // Headless output keeps the size asked for, so nothing needs this machine's drawing speed.
    capability::Capability measured =
        headless ? capability::measure_memory() : capability::measure_machine();
    mark(headless ? "memory measured" : "machine probe done");
    const std::optional<Codec> forced_codec = codec_from(codec_name);
    // Over loopback the link is this machine's memory: the probe would find no latency worth a
    // coarser start and raw bricks cheapest (docs/PROTOCOL.md, section 6), after costing the
    // start about 30 ms and soltexd the CPU of its probe bricks. An in-process source moves no
    // bytes, so a probe of it measures nothing. A simulated bandwidth needs the probe's zstd
    // figures to choose a codec.
    const bool loopback = !local && net::is_loopback_address(server);
    const bool probe_link =
        !local && !scene.objects.empty() && (!loopback || override.bandwidth_mb_per_s.has_value());
    if (probe_link) {
      // The probe's own cache and source: its bricks are no part of the picture.
      BrickCache probe_cache(256u << 20);
      net::BrickFetcher probe(server, probe_cache, fetcher_options);
      measured.round_trip_ms = static_cast<double>(probe.measure_round_trip().count()) / 1e3;
      mark(fmt::format("connected: GetServerInfo answered in {:.2f} ms", measured.round_trip_ms));
      capability::measure_link(probe, scene.objects.front().material.texture, measured,
                               !forced_codec.has_value());
      mark("link probe done");
    } else if (loopback) {
      measured.codec = Codec::raw;
    }
    const capability::Capability effective = capability::apply(measured, override);
    // Headless output, and a window given a size, keep the size asked for exactly; a window
    // showing the scene's size shrinks it to what this machine draws in time.
    capability::ChoiceLimits limits;
    limits.scale_frame = !headless && width == 0 && height == 0;
    // A headless run shows nothing before it converges: a coarse start only guards its time
    // limit, so the start level's bricks may take half of it (a window starts within 1.5 s).
    if (headless) limits.fetch_seconds = std::max(limits.fetch_seconds, max_seconds / 2.0);
    capability::Choice choice =
        capability::choose(effective, scene, width > 0 ? width : scene.image.width,
                           height > 0 ? height : scene.image.height, limits);
    if (finest_level > 0) {
      choice.finest_level_log2 = finest_level;
      choice.start_level_log2 = std::min(choice.start_level_log2, finest_level);
    }
    if (!local) {
      fetcher_options.codec = choose_codec(forced_codec, measured, override, probe_link);
    }
    auto cache = std::make_unique<BrickCache>(choice.cache_budget_bytes);
    std::unique_ptr<net::BrickSource> source;
    if (local) {
      source = std::make_unique<net::LocalBrickSource>(*cache);
    } else {
      auto fetcher = std::make_unique<net::BrickFetcher>(server, *cache, fetcher_options);
      if (!probe_link) {
        measured.round_trip_ms = static_cast<double>(fetcher->measure_round_trip().count()) / 1e3;
        mark(
            fmt::format("connected: GetServerInfo answered in {:.2f} ms (loopback: no link "
                        "probe)",
                        measured.round_trip_ms));
      }
      source = std::move(fetcher);
    }
    spdlog::info("capability: {}, {} MiB available, round trip {:.2f} ms, {}{}",
                 effective.pixels_per_second > 0.0
                     ? fmt::format("{:.1f} Mpixel/s", effective.pixels_per_second / 1e6)
                     : std::string("drawing speed not measured (the frame keeps its size)"),
                 effective.available_memory_mb, measured.round_trip_ms,
                 probe_link || local
                     ? fmt::format("brick latency {:.1f} ms, link {:.1f} MB/s",
                                   effective.brick_latency_ms, effective.bandwidth_mb_per_s)
                     : std::string("loopback link (not probed)"),
                 capability_text.empty() ? "" : " (simulated: " + capability_text + ")");
    for (std::size_t begin = 0; begin < choice.reason.size();) {
      const std::size_t end = choice.reason.find('\n', begin);
      spdlog::info("choice: {}", choice.reason.substr(begin, end - begin));
      begin = end == std::string::npos ? choice.reason.size() : end + 1;
    }
    const TextureResolution resolution{choice.finest_level_log2, brick_size,
                                       MipSettings{mip_from(mip_name), 2}};
    RenderOptions render_options;
    render_options.filter = filter_from(filter_name);
    render_options.access = access_from(access_name);
    render_options.antialias = antialias;
    render_options.edge_antialias = edge_antialias;
    render_options.level_bias = level_bias;
    render_options.false_colour_levels = false_colour;
    render_options.threads = threads;
#ifdef SOLTEX_HAVE_SDL2
    if (!headless) {
      for (const char* option :
           {"--out", "--exact", "--reference", "--supersample", "--max-time-s", "--timeline"}) {
        if (app.count(option) > 0) spdlog::warn("{} applies to --headless only; ignored", option);
      }
      return run_window(scene, resolution, *cache, *source, render_options, choice, window_frames,
                        screenshot);
    }
#endif
    mark("cache and brick source ready");
    const PreparedScene prepared = prepare_scene(scene, resolution, *source);
    mark("scene prepared, textures registered");
    FrameRenderer renderer(*cache, render_options);

    view::HeadlessOptions options;
    options.max_time = std::chrono::milliseconds(static_cast<long>(max_seconds * 1000));
    options.start_level_log2 = choice.start_level_log2;
    options.cache = cache.get();
    options.timeline = marks;
    std::ofstream record_file;
    std::optional<load::RequestLogWriter> recorder;
    if (!record_path.empty()) {
      record_file.open(record_path);
      if (!record_file) throw std::runtime_error("cannot write " + record_path.string());
      recorder.emplace(record_file);
      options.on_misses = [&](double seconds, const std::vector<net::BrickWant>& misses) {
        for (const net::BrickWant& w : misses) {
          recorder->append({seconds, w.key.level, w.key.brick.x, w.key.brick.y, w.key.brick.z,
                            static_cast<int32_t>(std::min<uint32_t>(w.screen_pixels, 1u << 30))});
        }
      };
    }
    const view::HeadlessResult result = view::render_until_converged(
        renderer, prepared, scene.camera, choice.width, choice.height, *source, options);
    mark(result.converged_ms >= 0.0 ? "converged" : "stopped, not converged");
    const net::SourceStats fetched = source->stats();
    const BrickCacheStats cached = cache->stats();
    std::printf("scene:      %s, %zu objects, %dx%d, finest level 2^%d, %s filter\n",
                scene.name.c_str(), scene.objects.size(), choice.width, choice.height,
                choice.finest_level_log2, filter_name.c_str());
    if (result.start_level_log2 < choice.finest_level_log2) {
      std::printf(
          "levels:     started at 2^%d (converged there after %.1f ms), refined to 2^%d%s\n",
          result.start_level_log2, result.start_converged_ms, result.refined_level_log2,
          result.refined_level_log2 < choice.finest_level_log2
              ? " (the cache budget holds no finer)"
              : "");
    }
    std::printf("frames:     %d; first frame after %.1f ms; ", result.frames,
                result.first_frame_ms);
    if (result.converged_ms >= 0.0) {
      std::printf("converged after %.1f ms\n", result.converged_ms);
    } else if (result.bricks_failed) {
      std::printf(
          "NOT converged: %llu bricks failed (refused, or corrupt after every refetch); "
          "drawn from what arrived\n",
          static_cast<unsigned long long>(fetched.errors));
    } else {
      std::printf("NOT converged within %.1f s (%zu bricks still missing)\n", max_seconds,
                  fetched.waiting + fetched.in_flight);
    }
    std::printf(
        "time:       %.1f ms drawing %d frames, %.1f ms waiting for bricks; %.1f ms of CPU here\n",
        result.drawing_ms, result.frames, result.waiting_ms, result.cpu_ms);
    std::printf(
        "last frame: %.2f ms (raster %.2f, shade %.2f), %zu pixels covered, %zu from a "
        "coarser level\n",
        result.last_frame_ms, result.last_stats.raster_ms, result.last_stats.shade_ms,
        result.last_stats.covered_pixels, result.last_stats.fallback_pixels);
    std::printf(
        "bricks:     %llu received, %.2f MB, %llu errors, %llu corrupt (refetched), %llu "
        "cancelled, %llu reconnects\n",
        static_cast<unsigned long long>(fetched.received), fetched.bytes / 1e6,
        static_cast<unsigned long long>(fetched.errors),
        static_cast<unsigned long long>(fetched.corrupt),
        static_cast<unsigned long long>(fetched.cancelled),
        static_cast<unsigned long long>(fetched.reconnects));
    double dense_bytes = 0.0;  // every object's volume as a dense 8-bit cube at its finest level
    for (const PreparedObject& o : prepared.objects) {
      const double side = std::ldexp(1.0, o.volume.finest_level_log2) + 1.0;
      dense_bytes += side * side * side * o.channels;
    }
    std::printf(
        "traffic:    %.2f MB fetched = %.2f %% of the dense cubes (%.1f MB of 8-bit samples)\n",
        fetched.bytes / 1e6, 100.0 * static_cast<double>(fetched.bytes) / dense_bytes,
        dense_bytes / 1e6);
    std::printf("cache:      %llu bricks, %.1f MB resident, hit rate %.2f %%\n",
                static_cast<unsigned long long>(cached.resident_bricks),
                cached.resident_bytes / 1e6, 100.0 * cached.hit_rate());
    if (!out.parent_path().empty()) std::filesystem::create_directories(out.parent_path());
    write_png(out, result.image);
    std::printf("wrote:      %s\n", out.c_str());
    if (marks != nullptr) marks->print(stdout);
    if (reference) {
      // Timed on a second call, as the cached frame is: the first faults in the reference's
      // buffers, which is not what per-pixel evaluation costs.
      renderer.render_reference(prepared, scene.camera, choice.width, choice.height, supersample);
      const auto ref_start = std::chrono::steady_clock::now();
      const Image ref = renderer.render_reference(prepared, scene.camera, choice.width,
                                                  choice.height, supersample);
      const double ref_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - ref_start)
              .count();
      const Frame warm = renderer.render(prepared, scene.camera, choice.width, choice.height);
      const double warm_ms = warm.stats.raster_ms + warm.stats.shade_ms;
      std::filesystem::path ref_path = out;
      ref_path.replace_filename(out.stem().string() + "-reference.png");
      write_png(ref_path, ref);
      std::printf(
          "reference:  %.1f ms per pixel-evaluated frame (%dx supersampled) vs %.2f ms "
          "cached: %.1fx; PSNR %.2f dB; wrote %s\n",
          ref_ms, supersample, warm_ms, ref_ms / warm_ms, psnr(result.image, ref),
          ref_path.c_str());
    }
    return result.converged_ms >= 0.0 ? kExitConverged : kExitNotConverged;
  } catch (const SceneError& e) {
    std::fprintf(stderr, "soltex-view: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::invalid_argument& e) {
    // A bad --capability item or a refused texture spec: the input, named in the message.
    std::fprintf(stderr, "soltex-view: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soltex-view: %s\n", e.what());
    return kExitFailure;
  }
}
