#include "accuracy_run.h"

#include <algorithm>
#include <memory>
#include <numeric>
#include <random>

#include "machine_info.h"
#include "pareto_front.h"
#include "percentile.h"
#include "progress_bar.h"
#include "soltex/common/brick_cache.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/prepared_scene.h"
#include "stopwatch.h"

namespace soltex::bench {
namespace {

FrameTime frame_time(const std::vector<double>& ms) {
  return {percentile(ms, 0.5), percentile(ms, 0.25), percentile(ms, 0.75)};
}

// A file name for a setting's frame: its position and label, spaces and '=' made safe.
std::string image_name(std::size_t index, const std::string& label) {
  std::string name = std::to_string(index);
  if (index < 10) name.insert(name.begin(), '0');
  name += '-';
  for (char c : label) name += (c == ' ' || c == '=') ? '-' : c;
  return name + ".png";
}

// Marks the results whose frame is on the Pareto front; settings that share a frame share a
// point.
void mark_front(std::vector<SettingResult>& results, FrameClock clock) {
  std::vector<TimeAccuracy> points;
  std::vector<std::size_t> point_of(results.size());
  for (std::size_t i = 0; i < results.size(); ++i) {
    const SettingResult& r = results[i];
    const auto group = static_cast<std::size_t>(r.frame_group);
    if (group == i) {
      points.push_back({front_time(r, clock).median_ms, r.error.psnr_db});
      point_of[i] = points.size() - 1;
    } else {
      point_of[i] = point_of[group];  // groups start at their first result, so it is set
    }
  }
  const std::vector<bool> front = pareto_front(points);
  for (std::size_t i = 0; i < results.size(); ++i) results[i].on_front = front[point_of[i]];
}

}  // namespace

const char* frame_clock_name(FrameClock clock) {
  return clock == FrameClock::cpu ? "cpu" : "wall";
}

AccuracyRun run_accuracy_sweep(const Scene& scene, const std::string& scene_name,
                               std::span<const AccuracySetting> settings,
                               const SweepOptions& options) {
  AccuracyRun run;
  run.scene_name = scene_name;
  for (const SceneObject& object : scene.objects) {
    const TextureSpec& texture = object.material.texture;
    run.automatic_access.push_back({object.name, texture_kind_name(texture),
                                    evaluated_per_pixel(texture, TextureAccess::automatic)});
  }
  run.options = options;
  run.machine = machine_description();
  run.load_before = load_average();
  const int width = options.size.width, height = options.size.height;
  ProgressBar progress(1 + static_cast<int>(settings.size()) + options.rounds);
  int done = 0;
  if (!options.images.empty()) std::filesystem::create_directories(options.images);

  // The reference: the texture evaluated per sub-pixel, band-limited to each sub-pixel's
  // footprint. The textures are registered only to prepare the scene; no brick is made.
  progress.show(done, "reference (per-pixel evaluation, 4x4 supersampled)");
  BrickCache reference_cache(std::size_t{1} << 20);
  net::LocalBrickSource reference_source(reference_cache);
  const PreparedScene reference_scene = prepare_scene(scene, TextureResolution{}, reference_source);
  RenderOptions reference_options;
  reference_options.threads = options.threads;
  FrameRenderer reference_renderer(reference_cache, reference_options);
  const Stopwatch reference_stopwatch;
  const Image reference = reference_renderer.render_reference(reference_scene, scene.camera, width,
                                                              height, run.reference_supersample);
  run.reference_ms = reference_stopwatch.elapsed().wall_ms;
  const Image per_pixel =
      reference_renderer.render_reference(reference_scene, scene.camera, width, height, 1);
  run.per_pixel_error = image_error(per_pixel, reference);
  if (!options.images.empty()) {
    write_png(options.images / "reference.png", reference);
    write_png(options.images / "per-pixel.png", per_pixel);
  }
  ++done;

  // Each distinct frame converged once; settings that differ in codec alone share it.
  std::vector<std::unique_ptr<FrameUnderTest>> frames;
  std::vector<std::size_t> frame_of;   // per result
  std::vector<BrickCostMeter> meters;  // per result
  for (const AccuracySetting& setting : settings) {
    progress.show(done, setting.label());
    SettingResult result;
    result.setting = setting;
    result.frame_group = static_cast<int>(run.results.size());
    std::size_t frame = frames.size();
    for (std::size_t i = 0; i < run.results.size(); ++i) {
      if (run.results[i].setting.same_frame_as(setting)) {
        result.frame_group = run.results[i].frame_group;
        frame = frame_of[i];
        break;
      }
    }
    if (frame == frames.size()) {
      frames.push_back(std::make_unique<FrameUnderTest>(scene, setting, options.size,
                                                        options.threads, options.max_converge));
    }
    const FrameUnderTest& drawn = *frames[frame];
    // Every row has its PNG; rows that share a frame (codec alone differs) the same pixels.
    if (!options.images.empty()) {
      write_png(options.images / image_name(run.results.size(), setting.label()), drawn.image());
    }
    result.error = image_error(drawn.image(), reference);
    result.resident_bytes = drawn.resident_bytes();
    result.covered_pixels = drawn.covered_pixels();
    result.evaluated_pixels = drawn.evaluated_pixels();
    meters.push_back(drawn.brick_cost_meter(setting.codec));
    run.results.push_back(result);
    frame_of.push_back(frame);
    ++done;
  }

  // Rounds: every frame once, in an order shuffled per round (so that no setting always
  // follows the same one, or the brick passes), one untimed frame first (the previous
  // setting's frame has just pushed this one's bricks out of the CPU caches), then the timed
  // ones; then one pass over every setting's bricks. Index frames.size() is the per-pixel
  // frame.
  std::vector<std::vector<double>> wall_ms(frames.size() + 1), cpu_ms(frames.size() + 1);
  std::vector<std::size_t> order(frames.size() + 1);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::mt19937 shuffle_order(1);  // a fixed seed: the same orders every run
  for (int round = 0; round < options.rounds; ++round) {
    progress.show(done, "measuring round " + std::to_string(round + 1) + "/" +
                            std::to_string(options.rounds));
    std::shuffle(order.begin(), order.end(), shuffle_order);
    for (const std::size_t f : order) {
      if (f < frames.size()) frames[f]->time_frame();
      for (int i = 0; i < options.frames_per_round; ++i) {
        Elapsed elapsed;
        if (f < frames.size()) {
          elapsed = frames[f]->time_frame();
        } else {
          const Stopwatch stopwatch;
          reference_renderer.render_reference(reference_scene, scene.camera, width, height, 1);
          elapsed = stopwatch.elapsed();
        }
        wall_ms[f].push_back(elapsed.wall_ms);
        cpu_ms[f].push_back(elapsed.cpu_ms);
      }
    }
    for (BrickCostMeter& meter : meters) meter.measure_pass();
    ++done;
  }
  progress.finish();
  for (std::size_t i = 0; i < run.results.size(); ++i) {
    run.results[i].frame = frame_time(wall_ms[frame_of[i]]);
    run.results[i].frame_cpu = frame_time(cpu_ms[frame_of[i]]);
    run.results[i].cost = meters[i].cost();
  }
  run.per_pixel_frame = frame_time(wall_ms.back());
  run.per_pixel_frame_cpu = frame_time(cpu_ms.back());
  mark_front(run.results, options.front_clock);
  run.load_after = load_average();
  return run;
}

}  // namespace soltex::bench
