#include "view_options.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <string>

#include "soltex/cli/tool_cli.h"
#include "soltex/scene/scene_loader.h"

namespace soltex::view {
namespace {

// A frame side: 0 for the scene's, else within the bounds a scene's image size has.
CLI::Validator FrameSide() {
  const std::string range = "[" + std::to_string(SceneLimits::kMinImageSide) + ", " +
                            std::to_string(SceneLimits::kMaxImageSide) + "]";
  return CLI::Validator(
      [range](std::string& text) -> std::string {
        if (text == "0") return {};
        if (const std::string problem =
                cli::IntegerIn(SceneLimits::kMinImageSide, SceneLimits::kMaxImageSide)(text);
            !problem.empty()) {
          return problem + " (or 0: the scene's)";
        }
        return {};
      },
      "0 or INTEGER in " + range);
}

// Where bricks and the scene come from.
void add_source_options(CLI::App& app, ViewOptions& o) {
  app.add_option("--server", o.server, "soltexd address HOST:PORT")
      ->check(soltex::cli::ServerAddress());
  app.add_flag("--local", o.local, "evaluate bricks in this process instead of fetching them");
  app.add_option("--scene", o.scene_path, "scene file (JSON); default: the built-in scene")
      ->check(CLI::ExistingFile);
  app.add_option("--capability", o.capability_text,
                 "simulate a weaker machine: cpu=FACTOR,mem=MB,bandwidth=MBPS");
  app.add_option("--codec", o.codec_name,
                 "how bricks travel: auto probes the link and takes raw where zstd's coding "
                 "costs more time than the bytes it saves, else zstd (a loopback server gets "
                 "raw without a probe); zstd, lz4 or raw force one")
      ->check(CLI::IsMember({"auto", "zstd", "lz4", "raw"}))
      ->capture_default_str();
  app.add_option("--record", o.record_path,
                 "write every brick request to FILE (soltex-load --mix replay plays it back)");
}

// How the run ends and what it writes: headless until converged, or a window.
void add_run_options(CLI::App& app, ViewOptions& o) {
  app.add_flag("--headless", o.headless, "render until converged, write --out, print statistics");
  app.add_option("--out", o.out, "PNG to write (headless; missing folders are made)")
      ->check(CLI::Validator(
          [](std::string& path) -> std::string {
            std::string extension = std::filesystem::path(path).extension().string();
            for (char& c : extension)
              c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            if (extension == ".png") return {};
            return "soltex-view writes PNG images: name the file NAME.png (" + path + ")";
          },
          "NAME.png"))
      ->capture_default_str();
  app.add_flag("--exact", o.exact,
               "wait for every brick, so the image depends on the settings alone (every "
               "headless run now does: one that does not converge exits 3)");
  app.add_flag("--reference", o.reference,
               "also render by evaluating the texture per pixel; print PSNR and speed ratio");
  app.add_option("--supersample", o.supersample, "reference sub-pixels per axis")
      ->check(cli::IntegerIn(1, 8))
      ->capture_default_str();
  app.add_option("--max-time-s,--max-seconds", o.max_seconds,
                 "give up converging after this many seconds (exit 3; --max-seconds: old name)")
      ->check(soltex::cli::NumberIn(0.1, 3600.0))
      ->capture_default_str();
  app.add_flag("--timeline", o.print_timeline,
               "headless: print when each step of the start happened (probes, frames, requests, "
               "each batch of bricks received), in ms since the program started");
  auto* headless_flag = app.get_option("--headless");
  app.add_option("--frames", o.window_frames,
                 "window: close after this many frames (0: when closed by the user)")
      ->check(cli::IntegerIn(0, 1000000))
      ->excludes(headless_flag);
  app.add_option("--screenshot", o.screenshot, "window: write the last frame shown to this PNG")
      ->excludes(headless_flag);
}

// What the picture is drawn at and how textures are read.
void add_picture_options(CLI::App& app, ViewOptions& o) {
  app.add_option("--filter", o.filter_name, "texture filter")
      ->check(CLI::IsMember({"nearest", "trilinear", "quadrilinear"}))
      ->capture_default_str();
  app.add_option("--mip", o.mip_name, "MIP construction")
      ->check(CLI::IsMember({"point", "band-limited", "supersampled"}))
      ->capture_default_str();
  app.add_option("--texture-access", o.access_name,
                 "how pixels read textures: auto evaluates the cheap analytic patterns (stripes, "
                 "checkers, rings, colour cube) per pixel and caches the rest; cache or evaluate "
                 "force one way for every texture")
      ->check(CLI::IsMember({"auto", "cache", "evaluate"}))
      ->capture_default_str();
  app.add_option("--antialias", o.antialias,
                 "sub-pixels per axis for silhouettes and clip edges (1: off); costs about "
                 "antialias^2 times the frame")
      ->check(cli::IntegerIn(1, 4))
      ->capture_default_str();
  app.add_option("--edge-antialias", o.edge_antialias,
                 "coverage samples per axis at edge pixels only (silhouettes, object and clip "
                 "edges, depth breaks), each surface there shaded once (0: off; 2 to 8)")
      ->check(CLI::IsMember({0, 2, 3, 4, 5, 6, 7, 8}))
      ->capture_default_str();
  app.add_option("--anisotropy", o.anisotropy,
                 "cached lookups along a footprint's long side at grazing angles: at most this "
                 "many, each at the level of its share (1: one lookup at the long side's level)")
      ->check(cli::IntegerIn(1, 16))
      ->capture_default_str();
  app.add_option("--level-bias", o.level_bias, "added to every pixel's level (negative: finer)")
      ->check(soltex::cli::NumberIn(-8.0, 8.0));
  app.add_flag("--false-colour", o.false_colour, "show each pixel's level in false colour");
  app.add_option("--threads", o.threads, "render threads (0: one per core)")
      ->check(cli::IntegerIn(0, 256));
  app.add_option("--finest-level", o.finest_level,
                 "finest texture level log2 the picture refines to (0: from the scene's size on "
                 "screen and this machine's memory; the link only sets where it starts)")
      ->check(cli::IntegerIn(0, 14));
  app.add_option("--brick-size", o.brick_size,
                 "cells per brick side: 16 draws warm frames faster, 8 fetches fewer bytes and "
                 "converges sooner from a cold start (docs/PERFORMANCE.md)")
      ->check(CLI::IsMember({8, 16}))
      ->capture_default_str();
  app.add_option("--width", o.width,
                 "frame width (0: the scene's; a window scales the scene's to this machine)")
      ->check(FrameSide());
  app.add_option("--height", o.height,
                 "frame height (0: the scene's; a window scales the scene's to this machine)")
      ->check(FrameSide());
}

MipMode mip_mode(const std::string& mip_name) {
  if (mip_name == "point") return MipMode::point;
  if (mip_name == "supersampled") return MipMode::supersampled;
  return MipMode::band_limited;
}

}  // namespace

std::optional<Codec> ViewOptions::forced_codec() const {
  if (codec_name == "zstd") return Codec::zstd;
  if (codec_name == "lz4") return Codec::lz4;
  if (codec_name == "raw") return Codec::raw;
  return std::nullopt;  // auto: the link's choice
}

TextureResolution ViewOptions::texture_resolution(int finest_level_log2) const {
  return TextureResolution{finest_level_log2, brick_size, MipSettings{mip_mode(mip_name), 2}};
}

std::chrono::milliseconds ViewOptions::server_wait(std::chrono::milliseconds most) const {
  if (!headless) return most;
  return std::min(most,
                  std::chrono::milliseconds(static_cast<int64_t>(std::ceil(max_seconds * 1000.0))));
}

RenderOptions ViewOptions::render_options() const {
  RenderOptions options;
  options.filter = filter_name == "nearest"        ? SampleFilter::nearest
                   : filter_name == "quadrilinear" ? SampleFilter::quadrilinear
                                                   : SampleFilter::trilinear;
  options.access = access_name == "cache"      ? TextureAccess::cached
                   : access_name == "evaluate" ? TextureAccess::evaluated
                                               : TextureAccess::automatic;
  options.antialias = antialias;
  options.edge_antialias = edge_antialias;
  options.anisotropy = anisotropy;
  options.level_bias = level_bias;
  options.false_colour_levels = false_colour;
  options.threads = threads;
  return options;
}

void add_view_options(CLI::App& app, ViewOptions& options) {
  add_source_options(app, options);
  add_run_options(app, options);
  add_picture_options(app, options);
}

}  // namespace soltex::view
