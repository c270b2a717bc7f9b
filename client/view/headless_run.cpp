#include "headless_run.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <stdexcept>

#include "headless_session.h"
#include "refused_textures.h"
#include "request_log.h"
#include "soltex/cli/tool_cli.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/image.h"

namespace soltex::view {
namespace {

// The finest level the scene's objects refine to: the client's choice, and the levels of
// materials that set their own ("2^8, set by every material", "2^12; 2^8 where a material
// sets its own").
std::string finest_levels_text(const Scene& scene, int chosen_log2) {
  std::set<int> own;
  std::size_t chosen_objects = 0;
  for (const SceneObject& object : scene.objects) {
    if (object.material.volume.finest_level_log2) {
      own.insert(*object.material.volume.finest_level_log2);
    } else {
      ++chosen_objects;
    }
  }
  std::string own_text;
  for (const int level : own)
    own_text += (own_text.empty() ? "" : ", ") + fmt::format("2^{}", level);
  if (own.empty()) return fmt::format("2^{}", chosen_log2);
  if (chosen_objects == 0) {
    return fmt::format("{}, set by every material", own_text);
  }
  return fmt::format("2^{}; {} where a material sets its own", chosen_log2, own_text);
}

void print_outcome(const ViewOptions& options, const Scene& scene, const ViewSetup& setup,
                   const HeadlessResult& result, const net::SourceStats& fetched) {
  const capability::Choice& choice = setup.choice;
  std::printf("scene:      %s, %zu objects, %dx%d, finest level %s, %s filter\n",
              scene.name.c_str(), scene.objects.size(), choice.width, choice.height,
              finest_levels_text(scene, choice.finest_level_log2).c_str(),
              options.filter_name.c_str());
  if (result.start_level_log2 < choice.finest_level_log2) {
    std::printf("levels:     started at 2^%d (converged there after %.1f ms), refined to 2^%d%s\n",
                result.start_level_log2, result.start_converged_ms, result.refined_level_log2,
                result.refined_level_log2 < choice.finest_level_log2
                    ? " (the cache budget holds no finer)"
                    : "");
  }
  std::printf("frames:     %d; first frame after %.1f ms; ", result.frames, result.first_frame_ms);
  if (result.converged_ms >= 0.0) {
    std::printf("converged after %.1f ms\n", result.converged_ms);
  } else if (result.bricks_failed) {
    std::printf(
        "NOT converged: %llu bricks failed (refused, or corrupt after every refetch); "
        "drawn from what arrived\n",
        static_cast<unsigned long long>(fetched.errors));
  } else {
    std::printf("NOT converged within %.1f s (%zu bricks still missing)\n", options.max_seconds,
                fetched.waiting + fetched.in_flight);
  }
  std::printf(
      "time:       %.1f ms drawing %d frames, %.1f ms waiting for bricks; %.1f ms of CPU here\n",
      result.drawing_ms, result.frames, result.waiting_ms, result.cpu_ms);
  // fallback_pixels counts the empty ones too: a pixel with no level at all did not get a
  // coarser one.
  const FrameStats& last = result.last_stats;
  std::printf(
      "last frame: %.2f ms (raster %.2f, shade %.2f), %zu pixels covered, %zu from a "
      "coarser level, %zu with no texture yet, %zu looked up in %zu anisotropic taps\n",
      result.last_frame_ms, last.raster_ms, last.shade_ms, last.covered_pixels,
      last.fallback_pixels - std::min(last.empty_pixels, last.fallback_pixels), last.empty_pixels,
      last.tapped_pixels, last.taps);
}

void print_traffic(const PreparedScene& prepared, const net::SourceStats& fetched,
                   const BrickCacheStats& cached) {
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
      "traffic:    %.2f MB fetched = %.3g %% of the dense cubes (%.1f MB of 8-bit samples)\n",
      fetched.bytes / 1e6, 100.0 * static_cast<double>(fetched.bytes) / dense_bytes,
      dense_bytes / 1e6);
  std::printf("cache:      %llu bricks, %.1f MB resident, hit rate %.2f %%\n",
              static_cast<unsigned long long>(cached.resident_bricks), cached.resident_bytes / 1e6,
              100.0 * cached.hit_rate());
}

// The per-pixel reference beside the converged frame: its time against a warm cached frame's,
// its PSNR, and the reference image next to --out.
void print_reference(const ViewOptions& options, const Scene& scene, const ViewSetup& setup,
                     const PreparedScene& prepared, FrameRenderer& renderer, const Image& image) {
  const int width = setup.choice.width, height = setup.choice.height;
  // Timed on a second call, as the cached frame is: the first faults in the reference's
  // buffers, which is not what per-pixel evaluation costs.
  renderer.render_reference(prepared, scene.camera, width, height, options.supersample);
  const auto ref_start = std::chrono::steady_clock::now();
  const Image ref =
      renderer.render_reference(prepared, scene.camera, width, height, options.supersample);
  const double ref_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - ref_start)
          .count();
  const Frame warm = renderer.render(prepared, scene.camera, width, height);
  const double warm_ms = warm.stats.raster_ms + warm.stats.shade_ms;
  std::filesystem::path ref_path = options.out;
  ref_path.replace_filename(options.out.stem().string() + "-reference.png");
  write_png(ref_path, ref);
  std::printf(
      "reference:  %.1f ms per pixel-evaluated frame (%dx supersampled) vs %.2f ms "
      "cached: %.1fx; PSNR %.2f dB; wrote %s\n",
      ref_ms, options.supersample, warm_ms, ref_ms / warm_ms, psnr(image, ref), ref_path.c_str());
}

}  // namespace

int run_headless(const ViewOptions& options, const Scene& scene, ViewSetup& setup,
                 StartupTimeline* timeline) {
  mark_on(timeline, "cache and brick source ready");
  PreparedScene prepared = prepare_scene(
      scene, options.texture_resolution(setup.choice.finest_level_log2), *setup.source);
  warn_of_refused_textures(prepared);
  mark_on(timeline, "scene prepared, textures registered");
  FrameRenderer renderer(*setup.cache, options.render_options());

  HeadlessOptions headless;
  headless.max_time = std::chrono::milliseconds(static_cast<long>(options.max_seconds * 1000));
  headless.start_level_log2 = setup.choice.start_level_log2;
  headless.cache = setup.cache.get();
  headless.timeline = timeline;
  std::ofstream record_file;
  std::optional<load::RequestLogWriter> recorder;
  if (!options.record_path.empty()) {
    record_file.open(options.record_path);
    if (!record_file) throw std::runtime_error("cannot write " + options.record_path.string());
    recorder.emplace(record_file);
    headless.on_misses = [&](double seconds, const std::vector<net::BrickWant>& misses) {
      for (const net::BrickWant& w : misses) {
        recorder->append({seconds, w.key.level, w.key.brick.x, w.key.brick.y, w.key.brick.z,
                          static_cast<int32_t>(std::min<uint32_t>(w.screen_pixels, 1u << 30))});
      }
    };
  }
  const HeadlessResult result =
      render_until_converged(renderer, prepared, scene.camera, setup.choice.width,
                             setup.choice.height, *setup.source, headless);
  mark_on(timeline, result.converged_ms >= 0.0 ? "converged" : "stopped, not converged");
  const net::SourceStats fetched = setup.source->stats();
  print_outcome(options, scene, setup, result, fetched);
  print_traffic(prepared, fetched, setup.cache->stats());
  if (!options.out.parent_path().empty()) {
    std::filesystem::create_directories(options.out.parent_path());
  }
  write_png(options.out, result.image);
  std::printf("wrote:      %s\n", options.out.c_str());
  if (timeline != nullptr) timeline->print(stdout);
  if (options.reference) print_reference(options, scene, setup, prepared, renderer, result.image);
  return result.converged_ms >= 0.0 ? cli::kExitOk : cli::kExitNotConverged;
}

}  // namespace soltex::view
