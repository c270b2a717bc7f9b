// Brick evaluation cost: one B = 16 brick ((B + 1)^3 samples, RGB) per iteration, single
// thread, for several patterns and MIP modes, at the finest and a coarse level.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/scene/default_scene.h"
#include "soltex/scene/texture_volume.h"

namespace {

using namespace soltex;

Pattern pattern_by_index(int index) {
  switch (index) {
    case 0:
      return MarbleParams{};
    case 1:
      return WoodParams{};
    case 2:
      return TurbulenceParams{};
    case 3:
      return NoiseParams{8.0, NoiseBasis::gradient};
    case 4:
      return CheckerParams{glm::dvec3(0.1), 0.0, true};
    default:
      return ColourCubeParams{0.5};
  }
}

void BM_EvaluateBrick(benchmark::State& state) {
  TextureSpec spec;
  spec.pattern = pattern_by_index(static_cast<int>(state.range(0)));
  const TextureEvaluator texture(spec);
  Volume volume;
  volume.min = glm::dvec3(-1.0);
  volume.max = glm::dvec3(1.0);
  volume.finest_level_log2 = 8;
  const BrickLayout layout(volume, 16);
  const int level = static_cast<int>(state.range(1));
  const MipSettings mip{static_cast<MipMode>(state.range(2)), 2};
  std::vector<float> out(static_cast<std::size_t>(layout.samples_per_brick()) * 3);
  const int bricks = layout.bricks_per_axis(level);
  int next = 0;
  for (auto _ : state) {
    const int b = next++ % (bricks * bricks * bricks);
    evaluate_brick(texture, layout, level,
                   {b % bricks, (b / bricks) % bricks, b / (bricks * bricks)}, mip, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetLabel(std::string(pattern_name(spec.pattern)) + " level " + std::to_string(level) + " " +
                 mip_mode_name(mip.mode));
  state.SetItemsProcessed(state.iterations());  // bricks/s; the time column is per brick
}

void BrickArguments(benchmark::internal::Benchmark* b) {
  for (int pattern = 0; pattern < 6; ++pattern) b->Args({pattern, 0, 1});
  b->Args({0, 0, 0});  // marble: point sampling at level 0
  b->Args({0, 3, 0});  // marble: point sampling at a coarse level
  b->Args({0, 3, 1});  // marble: band-limited at a coarse level: fewer octaves
  b->Args({0, 0, 2});  // marble: supersampled 2^3
}

BENCHMARK(BM_EvaluateBrick)->Apply(BrickArguments)->ArgNames({"pattern", "level", "mip"});

// The default scene's textures as soltexd evaluates them for soltex-view's cold start: the
// object's spec and texture volume at the client's finest level 2^8 (soltex-view's choice for
// the default scene), B = 16, band-limited, level 0 or 1 (nearly all of the start's bricks),
// the bricks of the level's cube in turn. object: 0 marble sphere, 1 wood torus, 2 checker box,
// 3 turbulence floor.
void BM_DefaultSceneBrick(benchmark::State& state) {
  static const Scene scene = default_scene();
  const SceneObject& object = scene.objects.at(static_cast<std::size_t>(state.range(0)));
  const TextureEvaluator texture(object.material.texture);
  const BrickLayout layout(texture_volume(object, 8), 16);
  const int level = static_cast<int>(state.range(1));
  const MipSettings mip{MipMode::band_limited, 2};
  std::vector<float> out(static_cast<std::size_t>(layout.samples_per_brick()) * 3);
  const int bricks = layout.bricks_per_axis(level);
  int next = 0;
  for (auto _ : state) {
    const int b = next++ % (bricks * bricks * bricks);
    evaluate_brick(texture, layout, level,
                   {b % bricks, (b / bricks) % bricks, b / (bricks * bricks)}, mip, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetLabel(object.name + " level " + std::to_string(level));
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_DefaultSceneBrick)->ArgsProduct({{0, 1, 2, 3}, {0, 1}})->ArgNames({"object", "level"});

// The bricks of soltex-load's cold mix (`--mix uniform --finest-level 10`): 6-octave marble,
// RGB, B = 16, band-limited, every brick of the L = 10 pyramid equally likely (7 of 8 are at
// level 0). The work one soltexd worker does per cold brick, without the serving: evaluation
// alone (encode = 0), or evaluation then encode_brick_samples() with the predictor and zstd at
// `zstd_level` (encode = 1; soltexd's default is -200). The same bricks in the same order on
// every run.
void BM_ColdMixBrick(benchmark::State& state) {
  TextureSpec spec;
  spec.pattern = MarbleParams{};
  const TextureEvaluator texture(spec);
  Volume volume;
  volume.min = glm::dvec3(-1.0);
  volume.max = glm::dvec3(1.0);
  volume.finest_level_log2 = static_cast<int>(state.range(0));
  const BrickLayout layout(volume, 16);
  const bool encode = state.range(1) != 0;
  const int zstd_level = static_cast<int>(state.range(2));
  const MipSettings mip{MipMode::band_limited, 2};
  std::vector<float> out(static_cast<std::size_t>(layout.samples_per_brick()) * 3);
  uint64_t total = 0;
  for (int level = 0; level <= layout.coarsest_level(); ++level) {
    const auto n = static_cast<uint64_t>(layout.bricks_per_axis(level));
    total += n * n * n;
  }
  std::mt19937_64 rng(1);
  std::size_t bytes = 0;
  for (auto _ : state) {
    uint64_t index = std::uniform_int_distribution<uint64_t>(0, total - 1)(rng);
    int level = 0;
    for (;; ++level) {
      const auto n = static_cast<uint64_t>(layout.bricks_per_axis(level));
      if (index < n * n * n) break;
      index -= n * n * n;
    }
    const auto n = static_cast<uint64_t>(layout.bricks_per_axis(level));
    const glm::ivec3 brick(static_cast<int>(index % n), static_cast<int>(index / n % n),
                           static_cast<int>(index / (n * n)));
    evaluate_brick(texture, layout, level, brick, mip, out);
    if (encode) {
      const std::string encoded =
          encode_brick_samples(out, 16, 3, CodecOptions{Codec::zstd, zstd_level});
      bytes += encoded.size();
      benchmark::DoNotOptimize(encoded.data());
    }
    benchmark::DoNotOptimize(out.data());
  }
  state.SetLabel(std::string("marble, cold mix of L = ") + std::to_string(state.range(0)) +
                 (encode ? ", evaluated and encoded (zstd " + std::to_string(zstd_level) + ")"
                         : std::string(", evaluated")));
  state.SetItemsProcessed(state.iterations());
  if (encode) state.counters["bytes_per_brick"] = static_cast<double>(bytes) / state.iterations();
}

BENCHMARK(BM_ColdMixBrick)
    ->Args({10, 0, 0})
    ->Args({10, 1, -200})
    ->Args({10, 1, 1})
    ->ArgNames({"finest", "encode", "zstd_level"});

}  // namespace

BENCHMARK_MAIN();
