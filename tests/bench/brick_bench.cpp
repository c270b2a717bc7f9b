// Brick evaluation cost: one B = 16 brick ((B + 1)^3 samples, RGB) per iteration, single
// thread, for several patterns and MIP modes, at the finest and a coarse level.
#include <benchmark/benchmark.h>

#include <vector>

#include "soltex/common/brick_evaluator.h"

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

}  // namespace

BENCHMARK_MAIN();
