// Texture evaluation throughput, single thread, on the grid noise libraries publish figures
// for: 64^3 points with lattice coordinate = index * 0.02 on each axis.
//
// Every texture is measured twice:
//   *_Single  the per-point function (value_noise, gradient_noise, fractal_sum,
//             TextureEvaluator::sample) called once per point, results summed into a sink;
//   *_Batch   FractalRows (one octave of weight 1 for plain noise): the x work once per
//             grid, then every row of 64 points;
//   *_Grid    TextureEvaluator::evaluate_grid over the whole 64^3 grid.
// items/s is points/s; the counter ns_per_point is its inverse in nanoseconds.
//
// Single-point loops pass each point through DoNotOptimize, so the compiler cannot hoist the
// y and z lattice work of the inlined noise functions out of the x loop: the figure is the
// cost of a call at an arbitrary point, as a ray marcher or a shader would make it.

#include <benchmark/benchmark.h>

#include <array>
#include <cstddef>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "soltex/common/fractal.h"
#include "soltex/common/gradient_noise.h"
#include "soltex/common/noise_tables.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/texture_spec.h"
#include "soltex/common/value_noise.h"

namespace {

constexpr int kSide = 64;
constexpr double kFrequency = 0.02;  // lattice cells per grid step
constexpr std::size_t kPoints = static_cast<std::size_t>(kSide) * kSide * kSide;

void report_points(benchmark::State& state) {
  const auto points = static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(kPoints);
  state.SetItemsProcessed(points);
  // Rate inverted: seconds per point; the 1e-9 factor turns it into nanoseconds per point.
  // The console reporter appends "s" to inverted rates: "8.2s" there reads 8.2 ns/point.
  state.counters["ns_per_point"] = benchmark::Counter(
      static_cast<double>(kPoints) * 1e-9,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// x coordinates 0, 1, ..., 63 (integer grid units); rows scale them by the frequency.
std::array<double, kSide> integer_row() {
  std::array<double, kSide> xs{};
  for (int i = 0; i < kSide; ++i) xs[static_cast<std::size_t>(i)] = static_cast<double>(i);
  return xs;
}

// ---- Single octave: value and gradient noise ----------------------------------------------

template <float (*Noise)(const soltex::NoiseTables&, const glm::dvec3&)>
void single_noise(benchmark::State& state) {
  const soltex::NoiseTables& tables = soltex::noise_tables();
  for (auto _ : state) {
    float sink = 0.0f;
    for (int k = 0; k < kSide; ++k) {
      for (int j = 0; j < kSide; ++j) {
        for (int i = 0; i < kSide; ++i) {
          glm::dvec3 p = glm::dvec3(i, j, k) * kFrequency;
          benchmark::DoNotOptimize(p);
          sink += Noise(tables, p);
        }
        benchmark::DoNotOptimize(sink);
      }
    }
  }
  report_points(state);
}

// The batch path: FractalRows over the grid's shared x row, every row of 64 points.
void batch_fractal(benchmark::State& state, const soltex::FractalParams& params) {
  const soltex::OctavePlan plan = soltex::plan_octaves(params, 0.0);
  const std::array<double, kSide> xs = integer_row();
  std::array<float, kSide> out{};
  for (auto _ : state) {
    const soltex::FractalRows rows(plan, xs);  // the x work, once per grid
    for (int k = 0; k < kSide; ++k) {
      for (int j = 0; j < kSide; ++j) {
        rows.sum(static_cast<double>(j), static_cast<double>(k), out);
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
      }
    }
  }
  report_points(state);
}

// One octave with weight 1 is the plain noise.
void batch_noise(benchmark::State& state, soltex::NoiseBasis basis) {
  batch_fractal(state, soltex::FractalParams{kFrequency, 0, 0, basis, true});
}

float value_noise_fn(const soltex::NoiseTables& tables, const glm::dvec3& t) {
  return soltex::value_noise(tables, t);
}
float gradient_noise_fn(const soltex::NoiseTables& tables, const glm::dvec3& t) {
  return soltex::gradient_noise(tables, t);
}

void BM_ValueNoise_Single(benchmark::State& state) {
  single_noise<value_noise_fn>(state);
}
void BM_ValueNoise_Batch(benchmark::State& state) {
  batch_noise(state, soltex::NoiseBasis::value);
}
void BM_GradientNoise_Single(benchmark::State& state) {
  single_noise<gradient_noise_fn>(state);
}
void BM_GradientNoise_Batch(benchmark::State& state) {
  batch_noise(state, soltex::NoiseBasis::gradient);
}

// ---- Six-octave fractals: octaves 0..5, octave 0 at 0.02 cells per grid step ---------------

soltex::FractalParams six_octaves(soltex::NoiseBasis basis, bool signed_octaves) {
  soltex::FractalParams params;
  params.scale = kFrequency;  // applied to integer points (i, j, k)
  params.octave_min = 0;
  params.octave_max = 5;
  params.basis = basis;
  params.signed_octaves = signed_octaves;
  return params;
}

void single_fractal(benchmark::State& state, const soltex::FractalParams& params) {
  const soltex::OctavePlan plan = soltex::plan_octaves(params, 0.0);
  for (auto _ : state) {
    float sink = 0.0f;
    for (int k = 0; k < kSide; ++k) {
      for (int j = 0; j < kSide; ++j) {
        for (int i = 0; i < kSide; ++i) sink += soltex::fractal_sum(plan, glm::dvec3(i, j, k));
        benchmark::DoNotOptimize(sink);
      }
    }
  }
  report_points(state);
}

// Turbulence: value basis (always non-negative, so signed_octaves does not apply).
void BM_ValueTurbulence6_Single(benchmark::State& state) {
  single_fractal(state, six_octaves(soltex::NoiseBasis::value, false));
}
void BM_ValueTurbulence6_Batch(benchmark::State& state) {
  batch_fractal(state, six_octaves(soltex::NoiseBasis::value, false));
}
// fBm: gradient basis, signed octaves.
void BM_GradientFbm6_Single(benchmark::State& state) {
  single_fractal(state, six_octaves(soltex::NoiseBasis::gradient, true));
}
void BM_GradientFbm6_Batch(benchmark::State& state) {
  batch_fractal(state, six_octaves(soltex::NoiseBasis::gradient, true));
}

// ---- Whole textures through TextureEvaluator ------------------------------------------------
//
// The grid spans the unit cube: 64 points per axis, step 1/64. Marble keeps its defaults
// except the turbulence scale, 1.28 cells per unit = 0.02 cells per grid step. Wood keeps all
// its defaults on the same points. Output: the default channels (R, G, B through the ramp);
// filter_width 0, so all six marble octaves are evaluated, as in the fractal benchmarks.

soltex::Grid unit_grid() {
  soltex::Grid grid;
  grid.origin = glm::dvec3(0.0);
  grid.step = glm::dvec3(1.0 / kSide);
  grid.count = glm::ivec3(kSide);
  return grid;
}

soltex::TextureSpec marble_spec() {
  soltex::MarbleParams marble;
  marble.turbulence.scale = kFrequency * kSide;
  soltex::TextureSpec spec;
  spec.pattern = marble;
  return spec;
}

soltex::TextureSpec wood_spec() {
  soltex::TextureSpec spec;
  spec.pattern = soltex::WoodParams{};
  return spec;
}

void single_texture(benchmark::State& state, const soltex::TextureSpec& spec) {
  const soltex::TextureEvaluator evaluator(spec);
  const soltex::Grid grid = unit_grid();
  for (auto _ : state) {
    float sink = 0.0f;
    for (int k = 0; k < kSide; ++k) {
      for (int j = 0; j < kSide; ++j) {
        for (int i = 0; i < kSide; ++i) {
          const soltex::Texel texel = evaluator.sample(grid.point(i, j, k), 0.0);
          sink += texel.colour.r + texel.colour.g + texel.colour.b;
        }
        benchmark::DoNotOptimize(sink);
      }
    }
  }
  report_points(state);
}

void grid_texture(benchmark::State& state, const soltex::TextureSpec& spec) {
  const soltex::TextureEvaluator evaluator(spec);
  const soltex::Grid grid = unit_grid();
  std::vector<float> out(grid.size() *
                         static_cast<std::size_t>(evaluator.spec().channels.sample_count()));
  for (auto _ : state) {
    evaluator.evaluate_grid(grid, 0.0, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  report_points(state);
}

void BM_Marble_Single(benchmark::State& state) {
  single_texture(state, marble_spec());
}
void BM_Marble_Grid(benchmark::State& state) {
  grid_texture(state, marble_spec());
}
void BM_Wood_Single(benchmark::State& state) {
  single_texture(state, wood_spec());
}
void BM_Wood_Grid(benchmark::State& state) {
  grid_texture(state, wood_spec());
}

}  // namespace

BENCHMARK(BM_ValueNoise_Single)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ValueNoise_Batch)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GradientNoise_Single)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GradientNoise_Batch)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ValueTurbulence6_Single)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ValueTurbulence6_Batch)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GradientFbm6_Single)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GradientFbm6_Batch)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Marble_Single)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Marble_Grid)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Wood_Single)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Wood_Grid)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
