#pragma once

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/prepared_scene.h"

namespace soltex::view {

// soltex-view's command line, as read: one field per option (`soltex-view --help`).
struct ViewOptions {
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
  int anisotropy = RenderOptions{}.anisotropy;
  double level_bias = 0.0;
  bool false_colour = false;
  double max_seconds = 30.0;
  int threads = 0;
  int finest_level = 0;
  int brick_size = 16;
  int width = 0;
  int height = 0;
  std::filesystem::path record_path;
  bool print_timeline = false;
  int window_frames = 0;
  std::filesystem::path screenshot;

  // --codec's codec; none for auto (the link's choice).
  std::optional<Codec> forced_codec() const;
  // The textures' volumes at `finest_level_log2` (the capability's choice, or --finest-level),
  // in --brick-size bricks with --mip's levels.
  TextureResolution texture_resolution(int finest_level_log2) const;
  // The renderer's settings named on the command line.
  RenderOptions render_options() const;
  // How long to wait for one answer from the server: `most`, and in a headless run no longer
  // than its --max-time-s.
  std::chrono::milliseconds server_wait(std::chrono::milliseconds most) const;
};

// Declares every soltex-view option on `app`, each writing into `options`.
void add_view_options(CLI::App& app, ViewOptions& options);

}  // namespace soltex::view
