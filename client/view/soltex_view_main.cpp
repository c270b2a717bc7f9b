// soltex-view: objects carved out of procedural solid textures, drawn in software from a local
// sparse brick cache that fills from soltexd (or from an in-process evaluator with --local).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "headless_run.h"
#include "soltex/cli/tool_cli.h"
#include "soltex/net/channel_security_options.h"
#include "soltex/raster/raster_view.h"
#include "soltex/scene/default_scene.h"
#include "soltex/scene/scene_error.h"
#include "soltex/scene/scene_loader.h"
#include "startup_timeline.h"
#include "view_options.h"
#include "view_setup.h"
#ifdef SOLTEX_HAVE_SDL2
#include "viewer_window.h"
#endif

namespace {

using namespace soltex;

// soltex-view's exit codes: the table every tool shares (README.md, "Exit codes").
// 0: the picture converged (a window: closed normally); 1: a runtime failure (the server, a
// file, the network); 2: a bad command line or scene, or no display for a window; 3: written
// but not converged, as --max-time-s ran out or bricks failed for good (refused, or corrupt
// each time).
constexpr int kExitFailure = cli::kExitFailure;
constexpr int kExitBadInput = cli::kExitUsage;

#ifdef SOLTEX_HAVE_SDL2
constexpr int kExitConverged = cli::kExitOk;

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

// Options typed on the command line that this run does not read: a warning each, so that a
// misunderstanding shows (an environment variable is left be: it may serve other runs).
void warn_of_unused_options(const CLI::App& app, const view::ViewOptions& options, int argc,
                            char** argv) {
  const auto typed = [&](const char* name) {
    return cli::on_command_line(*app.get_option(name), argc, argv);
  };
  if (typed("--supersample") && !options.reference) {
    spdlog::warn(
        "--supersample sets the --reference frame's sub-pixels: without --reference "
        "it is not used");
  }
  if (typed("--tls-server-name") && !typed("--tls-ca")) {
    spdlog::warn(
        "--tls-server-name names the certificate TLS checks: without --tls-ca there is "
        "no TLS, and it is not used");
  }
  if (!options.local) return;
  for (const char* name : {"--codec", "--token", "--token-file", "--tls-ca"}) {
    if (typed(name)) spdlog::warn("--local draws without a server: {} is not used", name);
  }
}

// A material's own finest_level_log2 is the scene author's, so --finest-level does not move
// it; where every material sets one, the option changes nothing and says so.
void warn_if_every_material_sets_its_level(const view::ViewOptions& options, const Scene& scene) {
  if (options.finest_level == 0 || scene.objects.empty()) return;
  const bool every = std::all_of(scene.objects.begin(), scene.objects.end(), [](const auto& o) {
    return o.material.volume.finest_level_log2.has_value();
  });
  if (every) {
    spdlog::warn(
        "--finest-level {} is not used: every material of the scene sets its own "
        "finest_level_log2",
        options.finest_level);
  }
}

// A command line that parsed but cannot run: which option is missing, or why a window cannot
// open; nullopt when it can run.
std::optional<int> refuse(const view::ViewOptions& options) {
  if (!options.local && options.server.empty()) {
    std::fprintf(stderr, "soltex-view: give --server HOST:PORT, or --local to run without one\n");
    return kExitBadInput;
  }
  if (options.local && !options.server.empty()) {
    // Not refused: SOLTEX_SERVER may be set for every tool in the environment.
    spdlog::warn("--local draws without a server: --server {} is not used", options.server);
  }
  // Written files must not overwrite what the run reads or writes besides (the scene, each
  // other): both would exit 0 with a file lost.
  if (!options.record_path.empty()) {
    std::error_code ignored;
    const auto same = [&](const std::filesystem::path& other) {
      return !other.empty() && (std::filesystem::equivalent(options.record_path, other, ignored) ||
                                std::filesystem::absolute(options.record_path, ignored) ==
                                    std::filesystem::absolute(other, ignored));
    };
    for (const auto& [name, path] :
         {std::pair{"--scene", options.scene_path}, std::pair{"--out", options.out}}) {
      if (!same(path)) continue;
      std::fprintf(stderr, "soltex-view: --record %s is the file %s names; give another\n",
                   options.record_path.string().c_str(), name);
      return kExitBadInput;
    }
  }
  // A level holds at least one brick on a side.
  const int brick_log2 = options.brick_size == 8 ? 3 : 4;
  if (options.finest_level > 0 && options.finest_level < brick_log2) {
    std::fprintf(stderr,
                 "soltex-view: --finest-level %d: must be 0 (chosen) or at least log2 of "
                 "--brick-size %d, %d\n",
                 options.finest_level, options.brick_size, brick_log2);
    return kExitBadInput;
  }
#ifndef SOLTEX_HAVE_SDL2
  if (!options.headless) {
    std::fprintf(stderr,
                 "soltex-view: this build has no window support; use --headless --out IMAGE.png\n");
    return kExitBadInput;
  }
#endif
  return std::nullopt;
}

// Before rendering: a frame or a reference too large to rasterize would fail only after the
// frame, with the rasterizer's words rather than the options'.
void check_frame_sizes(const view::ViewOptions& options, const capability::Choice& choice) {
  const int side = std::max(choice.width, choice.height);
  if (static_cast<int64_t>(side) * options.antialias > RasterView::kMaxSize) {
    throw std::invalid_argument("--antialias " + std::to_string(options.antialias) + " draws " +
                                std::to_string(static_cast<int64_t>(side) * options.antialias) +
                                " sub-pixels on a side, more than " +
                                std::to_string(RasterView::kMaxSize) + ": give --antialias " +
                                std::to_string(std::max(1, RasterView::kMaxSize / side)) +
                                " or less for a " + std::to_string(choice.width) + "x" +
                                std::to_string(choice.height) + " image");
  }
  if (!options.reference) return;
  if (static_cast<int64_t>(side) * options.supersample <= RasterView::kMaxSize) return;
  throw std::invalid_argument(
      "--reference at --supersample " + std::to_string(options.supersample) + " needs " +
      std::to_string(static_cast<int64_t>(side) * options.supersample) +
      " sub-pixels on a side, more than " + std::to_string(RasterView::kMaxSize) +
      ": give --supersample " + std::to_string(std::max(1, RasterView::kMaxSize / side)) +
      " or less for a " + std::to_string(choice.width) + "x" + std::to_string(choice.height) +
      " image");
}

int run(const view::ViewOptions& options, const CLI::App& app,
        const net::ChannelSecurityOptions& security, net::TokenOrigin token_origin,
        view::StartupTimeline& timeline) {
  net::FetcherOptions fetcher_options;
  fetcher_options.security = net::finish_channel_security(security, token_origin);
  fetcher_options.register_timeout = options.server_wait(fetcher_options.register_timeout);
  // Null marks nothing: the timeline costs only where it is printed.
  view::StartupTimeline* const marks =
      options.print_timeline && options.headless ? &timeline : nullptr;
  if (marks != nullptr) fetcher_options.on_event = view::fetch_marks(*marks);
  view::mark_on(marks, "command line read");
  const Scene scene = options.scene_path.empty() ? default_scene() : load_scene(options.scene_path);
  warn_if_every_material_sets_its_level(options, scene);
  view::ViewSetup setup = view::set_up_view(options, scene, fetcher_options, marks);
  check_frame_sizes(options, setup.choice);
#ifdef SOLTEX_HAVE_SDL2
  if (!options.headless) {
    for (const char* option :
         {"--out", "--exact", "--reference", "--supersample", "--max-time-s", "--timeline"}) {
      if (app.count(option) > 0) spdlog::warn("{} applies to --headless only; ignored", option);
    }
    return run_window(scene, options.texture_resolution(setup.choice.finest_level_log2),
                      *setup.cache, *setup.source, options.render_options(), setup.choice,
                      options.window_frames, options.screenshot);
  }
#else
  (void)app;
#endif
  return view::run_headless(options, scene, setup, marks);
}

}  // namespace

int main(int argc, char** argv) {
  view::StartupTimeline timeline;  // the program's start: the first thing it does
  CLI::App app{"soltex-view: software-rendered solid textures from a sparse brick cache"};
  view::ViewOptions options;
  std::string log_level = "info";
  cli::add_common_options(app, "soltex-view", log_level);
  view::add_view_options(app, options);
  net::ChannelSecurityOptions security_options;
  net::add_channel_security_options(app, security_options);
  if (const auto exit_code = cli::parse(app, "soltex-view", argc, argv)) return *exit_code;
  cli::start_logging("soltex-view", log_level);
  cli::prepare_for_grpc_streams();
  if (const auto exit_code = refuse(options)) return *exit_code;
  warn_of_unused_options(app, options, argc, argv);
  try {
    const net::TokenOrigin token_origin =
        cli::value_from_environment(*app.get_option("--token"), argc, argv)
            ? net::TokenOrigin::environment
            : net::TokenOrigin::typed;
    return run(options, app, security_options, token_origin, timeline);
  } catch (const SceneError& e) {
    std::fprintf(stderr, "soltex-view: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::invalid_argument& e) {
    // A bad --capability item or a refused texture spec: the input, named in the message.
    std::fprintf(stderr, "soltex-view: %s\n",
                 cli::with_value_source(app, e.what(), argc, argv).c_str());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soltex-view: %s\n", e.what());
    return kExitFailure;
  }
}
