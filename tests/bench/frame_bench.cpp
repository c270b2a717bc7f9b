// soltex-view's warm frame: deploy/scenes/bunny-marble.json (the Stanford bunny in marble on a
// wood floor) at 1280 x 720, every brick resident (converged once, from an in-process
// LocalBrickSource, before timing), finest level 2^8 where a material does not set its own
// (the bunny's marble sets 2^9).
//   BM_WarmFrame       FrameRenderer::render: raster + brick lookup + shade
//   BM_Raster          the rasterizer alone on the same view, into tile-sized G-buffers as
//                      FrameRenderer draws (its raster part, without shading)
//   BM_ReferenceFrame  FrameRenderer::render_reference: the texture evaluated per pixel
//   BM_ColdFrame       FrameRenderer::render with nothing resident (a client's first frame):
//                      every pixel misses, and the frame lists every brick it wants
// First argument: the thread count (the caller's thread included). Second: 0 for the scene as
// it is, 1 for the bunny alone (the floor removed): the wood floor's two-colour rings keep the
// whole frame at about 26 dB against the reference, the marble alone is above 40 dB, so the
// speed ratio at PSNR >= 40 dB is read from the second; 2 for the bunny alone drawn with both
// faces (the scene draws front faces only), to show what back-face culling saves; 3 for the
// built-in default scene instead (four objects; a clip plane cuts the marble sphere open, so
// the frame has caps); 4 for the bunny alone in bricks of 8 instead of 16. Times are
// wall-clock per frame; the CPU column is the whole process's CPU time (all render threads) per
// frame. Counters: the warm frame's raster and shade wall times (ms) as FrameRenderer reports them,
// and its PSNR against the per-pixel reference (dB).

#include <benchmark/benchmark.h>

#include <chrono>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "converge.h"
#include "soltex/common/brick_cache.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/raster/rasterizer.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/image.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/default_scene.h"
#include "soltex/scene/scene_loader.h"

namespace {

constexpr int kWidth = 1280;
constexpr int kHeight = 720;

// One converged scene per thread count, kept for the whole run.
struct WarmScene {
  WarmScene(int threads, int variant)
      : scene(load(variant)),
        cache(std::make_unique<soltex::BrickCache>(512u << 20)),
        source(std::make_unique<soltex::net::LocalBrickSource>(*cache)),
        prepared(soltex::prepare_scene(
            scene, soltex::TextureResolution{8, variant == 4 ? 8 : 16, {}}, *source)),
        renderer(std::make_unique<soltex::FrameRenderer>(
            *cache, soltex::RenderOptions{.threads = threads})) {
    converge(*renderer, prepared, scene.camera, kWidth, kHeight, *source, "frame_bench");
    const soltex::Image warm = renderer->render(prepared, scene.camera, kWidth, kHeight).image;
    psnr = soltex::psnr(warm, renderer->render_reference(prepared, scene.camera, kWidth, kHeight));
  }

  static soltex::Scene load(int variant) {
    if (variant == 3) return soltex::default_scene();  // 4: the bunny alone, bricks of 8
    soltex::Scene scene = soltex::load_scene(SOLTEX_SOURCE_DIR "/deploy/scenes/bunny-marble.json");
    if (variant >= 1) {
      std::erase_if(scene.objects, [](const soltex::SceneObject& o) { return o.name == "floor"; });
    }
    if (variant == 2) {
      for (soltex::SceneObject& object : scene.objects) object.double_sided = true;
    }
    return scene;
  }

  soltex::Scene scene;
  std::unique_ptr<soltex::BrickCache> cache;
  std::unique_ptr<soltex::net::LocalBrickSource> source;
  soltex::PreparedScene prepared;
  std::unique_ptr<soltex::FrameRenderer> renderer;
  double psnr = 0.0;
};

WarmScene& warm_scene(const benchmark::State& state) {
  constexpr int kThreadCounts = 3, kVariants = 5;  // threads 0..2, variants 0..4
  static std::unique_ptr<WarmScene> scenes[kThreadCounts][kVariants];
  const auto threads = static_cast<int>(state.range(0));
  const auto variant = static_cast<int>(state.range(1));
  if (threads < 0 || threads >= kThreadCounts || variant < 0 || variant >= kVariants) {
    throw std::out_of_range("frame_bench: no scene slot for these arguments");
  }
  auto& s = scenes[threads][variant];
  if (!s) s = std::make_unique<WarmScene>(threads, variant);
  return *s;
}

void BM_WarmFrame(benchmark::State& state) {
  WarmScene& w = warm_scene(state);
  double raster_ms = 0.0, shade_ms = 0.0;
  std::size_t covered = 0;
  for (auto _ : state) {
    soltex::Frame frame = w.renderer->render(w.prepared, w.scene.camera, kWidth, kHeight);
    if (!frame.complete()) state.SkipWithError("warm frame missed a brick");
    raster_ms += frame.stats.raster_ms;
    shade_ms += frame.stats.shade_ms;
    covered = frame.stats.covered_pixels;
    benchmark::DoNotOptimize(frame.image);
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["raster_ms"] = raster_ms / n;
  state.counters["shade_ms"] = shade_ms / n;
  state.counters["covered"] = static_cast<double>(covered);
  state.counters["psnr_db"] = w.psnr;
}

void BM_Raster(benchmark::State& state) {
  WarmScene& w = warm_scene(state);
  // The same view and objects FrameRenderer draws (eye-relative), through a rasterizer of its
  // own so that FrameRenderer's G-buffer stays untouched.
  soltex::Rasterizer rasterizer({.threads = static_cast<int>(state.range(0))});
  const soltex::Camera& camera = w.scene.camera;
  soltex::Camera at_origin = camera;
  at_origin.target = camera.target - camera.position;
  at_origin.position = glm::dvec3(0.0);
  const glm::dmat4 from_world = glm::translate(glm::dmat4(1.0), -camera.position);
  std::vector<soltex::RasterObject> objects;
  for (const soltex::PreparedObject& o : w.prepared.objects) {
    soltex::RasterObject object = o.raster;
    object.model = glm::mat4(from_world * o.world_from_object);
    objects.push_back(object);
  }
  soltex::RasterView view;
  view.width = kWidth;
  view.height = kHeight;
  view.view_projection = glm::mat4(soltex::view_projection(at_origin, kWidth, kHeight));
  std::size_t covered = 0;
  for (auto _ : state) {
    const soltex::RasterStats stats = rasterizer.render_tiles(
        view, objects, [](const soltex::GBuffer& tile, int, int, int, int, int) {
          benchmark::DoNotOptimize(tile.depth.data());
        });
    covered = stats.pixels_covered;
  }
  state.counters["covered"] = static_cast<double>(covered);
}

void BM_ReferenceFrame(benchmark::State& state) {
  WarmScene& w = warm_scene(state);
  for (auto _ : state) {
    soltex::Image image = w.renderer->render_reference(w.prepared, w.scene.camera, kWidth, kHeight);
    benchmark::DoNotOptimize(image);
  }
}

void BM_ColdFrame(benchmark::State& state) {
  WarmScene& w = warm_scene(state);
  std::size_t misses = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto empty = std::make_unique<soltex::BrickCache>(512u << 20);
    auto renderer = std::make_unique<soltex::FrameRenderer>(
        *empty, soltex::RenderOptions{.threads = static_cast<int>(state.range(0))});
    state.ResumeTiming();
    soltex::Frame frame = renderer->render(w.prepared, w.scene.camera, kWidth, kHeight);
    misses = frame.misses.size();
    benchmark::DoNotOptimize(frame.image);
    state.PauseTiming();
    renderer.reset();
    empty.reset();
    state.ResumeTiming();
  }
  state.counters["bricks_wanted"] = static_cast<double>(misses);
}

// Wall time per frame, with the whole process's CPU (all render threads) beside it.
void wall_and_process_cpu_ms(benchmark::internal::Benchmark* b) {
  b->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
}

BENCHMARK(BM_WarmFrame)
    ->Args({1, 0})
    ->Args({2, 0})
    ->Args({2, 1})
    ->Args({2, 2})
    ->Args({2, 3})
    ->Args({2, 4})
    ->Apply(wall_and_process_cpu_ms);
BENCHMARK(BM_Raster)->Args({1, 0})->Args({2, 0})->Args({2, 1})->Apply(wall_and_process_cpu_ms);
BENCHMARK(BM_ColdFrame)->Args({2, 0})->Args({2, 1})->Args({2, 4})->Apply(wall_and_process_cpu_ms);
BENCHMARK(BM_ReferenceFrame)
    ->Args({2, 0})
    ->Args({2, 1})
    ->Args({2, 2})
    ->Apply(wall_and_process_cpu_ms);

}  // namespace

BENCHMARK_MAIN();
