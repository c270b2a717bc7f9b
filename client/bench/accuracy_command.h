#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>

namespace soltex::bench {

// `soltex-bench accuracy`: what each accuracy knob costs in time, bytes and memory, measured
// on one scene and written as Markdown, CSV and an SVG plot.
struct AccuracyCommandOptions {
  std::filesystem::path scene;  // empty: the built-in default scene
  int width = 0;                // 0: 640, or 160 with --quick
  int height = 0;               // 0: 360, or 90 with --quick
  bool quick = false;           // a handful of settings on a tiny frame (the smoke test)
  std::filesystem::path out_dir = "docs";
  std::filesystem::path markdown;  // empty: out_dir/accuracy.md; likewise csv and svg
  std::filesystem::path csv;
  std::filesystem::path svg;
  int threads = 0;           // render threads, 0: one per core
  int rounds = 0;            // 0: 30, or 2 with --quick
  int frames_per_round = 0;  // 0: 2, or 1 with --quick
  double max_converge_seconds = 300.0;
  std::filesystem::path images;     // where to write every frame as PNG; empty: nowhere
  std::string front_clock = "cpu";  // the frame time the front and plot go by: cpu or wall
};

// Adds the subcommand to `app`; its options fill `options`.
CLI::App* add_accuracy_command(CLI::App& app, AccuracyCommandOptions& options);

// Runs the sweep and writes the three files; returns the process exit code (0 done, 1 a
// measurement failed, 2 the scene could not be used), with the reason on stderr.
int run_accuracy_command(const AccuracyCommandOptions& options);

}  // namespace soltex::bench
