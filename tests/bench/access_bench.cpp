// Cache or evaluate: what reading a texture costs per pixel, looked up in the brick cache or
// evaluated over the pixel's footprint, for every pattern kind, side by side.
//
// One object (a sphere filling most of a 640 x 480 frame, lit by one directional light) with
// the texture under test, finest level 2^8, bricks of 16, trilinear, every brick resident
// (converged once from an in-process LocalBrickSource before timing). Each iteration of
// BM_CacheOrEvaluate/<kind> draws the same warm frame twice, once with TextureAccess::cached
// and once with TextureAccess::evaluated, in alternating order, on one render thread (the
// caller's), and times each with the thread's CPU clock: machine noise then moves both alike.
// Counters (medians over the iterations, in ns per covered pixel):
//   cached_ns, evaluated_ns   the whole frame (raster, texture, lighting, write)
//   cached_shade_ns, evaluated_shade_ns   its shading part, as FrameStats::shade_ms reports it
//   evaluated_over_cached     evaluated_ns / cached_ns: below 1, evaluating is cheaper
// The raster part is the same in both frames, so the difference of the two frame costs is the
// difference of the two ways of reading the texture. A cached lookup's other costs (the
// server's evaluation, the bytes and the cache memory of its bricks) come on top and are not
// measured here (soltex-bench accuracy reports them).
//
// Argument: the kind, 0..8 = stripes, checker 2D, checker 3D, rings, colour cube, wood, noise,
// turbulence, marble. Run:
//   build/tests/bench/access_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only
// `access_bench --dump DIR` instead writes each kind's warm frames (cached, evaluated) and
// per-pixel reference as PNGs, to check that a change to either path keeps every byte.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "converge.h"
#include "cpu_samples.h"
#include "soltex/common/brick_cache.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/image.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/scene_loader.h"

namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;

struct Kind {
  const char* name;
  const char* texture;  // the scene's "texture" object
};

// Each pattern at a scale that shows several periods on the sphere.
constexpr std::array<Kind, 9> kKinds{{
    {"stripes", R"({"stripes": {"width": 0.2}})"},
    {"checker_2d", R"({"checker": {"size": [0.25, 0.25, 0.25]}})"},
    {"checker_3d", R"({"checker": {"size": [0.25, 0.25, 0.25], "three_d": true}})"},
    {"rings", R"({"rings": {"thickness": 0.15}})"},
    {"colour_cube", R"({"colour_cube": {"period": 0.5}})"},
    {"wood", R"({"wood": {}})"},
    {"noise", R"({"noise": {"scale": 4}})"},
    {"turbulence", R"({"turbulence": {"fractal": {"scale": 2, "octave_max": 6}}})"},
    {"marble", R"({"marble": {"frequency": 1.5, "amplitude": 4,
                              "turbulence": {"scale": 2, "octave_max": 6}}})"},
}};

std::string scene_json(const Kind& kind) {
  return std::string(R"({"image": {"width": 640, "height": 480},
    "camera": {"position": [0, 0.4, 2.6], "target": [0, 0, 0]},
    "lights": [{"directional": {"direction": [-0.5, -1, -0.7]}}],
    "objects": [{"mesh": {"sphere": {"radius": 1, "segments": 96, "rings": 48}},
                 "material": {"texture": )") +
         kind.texture + R"(, "specular": 0.3, "shininess": 32}}]})";
}

// One converged scene per kind, with a renderer per access, kept for the whole run.
struct WarmObject {
  explicit WarmObject(const Kind& kind)
      : scene(soltex::parse_scene(scene_json(kind), kind.name)),
        cache(std::make_unique<soltex::BrickCache>(256u << 20)),
        source(std::make_unique<soltex::net::LocalBrickSource>(*cache)),
        prepared(soltex::prepare_scene(scene, soltex::TextureResolution{8, 16, {}}, *source)),
        cached(std::make_unique<soltex::FrameRenderer>(
            *cache, soltex::RenderOptions{.access = soltex::TextureAccess::cached, .threads = 1})),
        evaluated(std::make_unique<soltex::FrameRenderer>(
            *cache,
            soltex::RenderOptions{.access = soltex::TextureAccess::evaluated, .threads = 1})) {
    converge(*cached, prepared, scene.camera, kWidth, kHeight, *source, "access_bench");
  }

  soltex::Scene scene;
  std::unique_ptr<soltex::BrickCache> cache;
  std::unique_ptr<soltex::net::LocalBrickSource> source;
  soltex::PreparedScene prepared;
  std::unique_ptr<soltex::FrameRenderer> cached, evaluated;
};

WarmObject& warm_object(std::size_t kind) {
  static std::array<std::unique_ptr<WarmObject>, kKinds.size()> objects;
  if (kind >= kKinds.size()) throw std::out_of_range("access_bench: no such kind");
  if (!objects[kind]) objects[kind] = std::make_unique<WarmObject>(kKinds[kind]);
  return *objects[kind];
}

struct Samples {
  std::vector<double> frame_ns, shade_ns;
};

// Draws one warm frame and records its thread CPU time and shading time per covered pixel.
void timed_frame(WarmObject& w, soltex::FrameRenderer& renderer, Samples& out,
                 benchmark::State& state) {
  const double start = cpu_clock_ns(CLOCK_THREAD_CPUTIME_ID);
  soltex::Frame frame = renderer.render(w.prepared, w.scene.camera, kWidth, kHeight);
  const double ns = cpu_clock_ns(CLOCK_THREAD_CPUTIME_ID) - start;
  if (!frame.complete()) state.SkipWithError("warm frame missed a brick");
  const auto covered = static_cast<double>(std::max<std::size_t>(1, frame.stats.covered_pixels));
  out.frame_ns.push_back(ns / covered);
  out.shade_ns.push_back(frame.stats.shade_ms * 1e6 / covered);
  benchmark::DoNotOptimize(frame.image);
}

void BM_CacheOrEvaluate(benchmark::State& state) {
  WarmObject& w = warm_object(static_cast<std::size_t>(state.range(0)));
  Samples cached, evaluated;
  bool cached_first = true;
  for (auto _ : state) {
    // Alternating the order keeps a cache-warming advantage off either side.
    if (cached_first) timed_frame(w, *w.cached, cached, state);
    timed_frame(w, *w.evaluated, evaluated, state);
    if (!cached_first) timed_frame(w, *w.cached, cached, state);
    cached_first = !cached_first;
  }
  const double c = median(cached.frame_ns), e = median(evaluated.frame_ns);
  state.counters["cached_ns"] = c;
  state.counters["evaluated_ns"] = e;
  state.counters["cached_shade_ns"] = median(cached.shade_ns);
  state.counters["evaluated_shade_ns"] = median(evaluated.shade_ns);
  state.counters["evaluated_over_cached"] = c > 0.0 ? e / c : 0.0;
  state.SetLabel(kKinds[static_cast<std::size_t>(state.range(0))].name);
}

BENCHMARK(BM_CacheOrEvaluate)
    ->DenseRange(0, static_cast<int>(kKinds.size()) - 1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void dump(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  for (std::size_t k = 0; k < kKinds.size(); ++k) {
    WarmObject& w = warm_object(k);
    const std::string name = kKinds[k].name;
    soltex::write_png(dir / (name + "-cached.png"),
                      w.cached->render(w.prepared, w.scene.camera, kWidth, kHeight).image);
    soltex::write_png(dir / (name + "-evaluated.png"),
                      w.evaluated->render(w.prepared, w.scene.camera, kWidth, kHeight).image);
    soltex::write_png(dir / (name + "-reference.png"),
                      w.evaluated->render_reference(w.prepared, w.scene.camera, kWidth, kHeight));
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::strcmp(argv[1], "--dump") == 0) {
    dump(argv[2]);
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
