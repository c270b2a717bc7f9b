#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "accuracy_setting.h"
#include "brick_cost.h"
#include "frame_under_test.h"
#include "image_error.h"
#include "soltex/scene/scene.h"

namespace soltex::bench {

// Which frame time the Pareto front and the plot go by. CPU time by default: on a shared
// machine the wall-clock medians of two identical frames can differ by more than the
// settings do, while CPU time separates them (docs/accuracy.md shows both).
enum class FrameClock { cpu, wall };

const char* frame_clock_name(FrameClock clock);  // "cpu", "wall"

struct SweepOptions {
  FrameSize size;
  int threads = 0;           // render threads, 0: one per core
  int rounds = 30;           // measuring rounds over all settings
  int frames_per_round = 2;  // timed frames per setting and round, after one untimed frame
  std::chrono::milliseconds max_converge{300000};
  std::filesystem::path images;  // where to write every frame as PNG; empty: nowhere
  FrameClock front_clock = FrameClock::cpu;
};

// Times of one setting's frames: the median and the quartiles around it.
struct FrameTime {
  double median_ms = 0.0;
  double q1_ms = 0.0;  // a quarter of the frames were faster
  double q3_ms = 0.0;  // a quarter were slower
};

// Everything measured for one setting.
struct SettingResult {
  AccuracySetting setting;
  ImageError error;                  // the converged frame against the reference
  FrameTime frame;                   // wall time of FrameRenderer::render, warm cache
  FrameTime frame_cpu;               // CPU time of the same frames, all render threads
  BrickCost cost;                    // the bricks the frame fetched, with the setting's codec
  uint64_t resident_bytes = 0;       // BrickCache::stats().resident_bytes once converged
  std::size_t covered_pixels = 0;    // of the converged frame
  std::size_t evaluated_pixels = 0;  // of those, evaluated per pixel rather than looked up
  int frame_group = 0;    // index of the first result drawing the same frame (codec aside)
  bool on_front = false;  // its frame is on the Pareto front of median time against PSNR
};

// How the renderer's automatic rule reads one object's texture (evaluated_per_pixel()).
struct TextureChoice {
  std::string object;
  std::string pattern;
  bool evaluated = false;
};

struct AccuracyRun {
  std::string scene_name;
  std::vector<TextureChoice> automatic_access;  // per scene object
  SweepOptions options;
  std::string machine;
  double load_before = -1.0;  // 1-minute load average when the sweep started and ended
  double load_after = -1.0;
  int reference_supersample = 4;
  double reference_ms = 0.0;
  // Per-pixel evaluation without the cache and without supersampling: the frame soltex-view
  // --reference draws, for scale.
  ImageError per_pixel_error;
  FrameTime per_pixel_frame;           // wall time
  FrameTime per_pixel_frame_cpu;       // timed in the same rounds as the settings
  std::vector<SettingResult> results;  // in sweep order
};

// The frame time the front goes by.
inline const FrameTime& front_time(const SettingResult& result, FrameClock clock) {
  return clock == FrameClock::cpu ? result.frame_cpu : result.frame;
}
inline const FrameTime& per_pixel_front_time(const AccuracyRun& run) {
  return run.options.front_clock == FrameClock::cpu ? run.per_pixel_frame_cpu : run.per_pixel_frame;
}

// Renders the reference once (per-pixel evaluation, 4x4 supersampled), then each setting's
// frame until it converges and measures its error, bricks and memory; then measures frame
// times and brick costs in rounds, each round going over every setting once. Shows progress
// on stderr.
AccuracyRun run_accuracy_sweep(const Scene& scene, const std::string& scene_name,
                               std::span<const AccuracySetting> settings,
                               const SweepOptions& options);

}  // namespace soltex::bench
