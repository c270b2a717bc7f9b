// The software rasterizer on one 1280 x 720 frame, milliseconds per frame.
//
// The mesh is a torus (major radius 1, minor radius 0.4) of 140 x 250 quads: 70,000
// triangles, 35,000 vertices with normals, built here (meshes are loaded elsewhere). The camera
// looks at it from 3.2 units, slightly from above, so it fills about a third of the frame and
// both faces of many triangles compete for pixels.
//   BM_RasterFrame         no clip planes (no clipping or capping work at all)
//   BM_RasterFrameCut      one clip plane through the torus: per-fragment tests on the
//                          straddling triangles and caps traced where the cut is seen
//   BM_RasterFrameSlab     two parallel planes keep a slab of it, the eye on the kept side
//                          of the far one: every triangle's fragments tested, and those past
//                          the slab kept, to tell where the view crosses it inside the solid
// The argument is the thread count (the caller's thread included). Times are wall-clock per
// frame; the CPU column is the whole process's CPU time (all render threads) per frame.

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/vec3.hpp>
#include <numbers>
#include <span>
#include <vector>

#include "soltex/raster/rasterizer.h"

namespace {

constexpr int kWidth = 1280;
constexpr int kHeight = 720;

struct Torus {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<uint32_t> indices;
};

Torus make_torus(int rings, int sides, float major, float minor) {
  Torus torus;
  const double pi = std::numbers::pi;
  for (int i = 0; i < rings; ++i) {
    const double u = 2.0 * pi * i / rings;
    for (int j = 0; j < sides; ++j) {
      const double v = 2.0 * pi * j / sides;
      const glm::vec3 normal(std::cos(u) * std::cos(v), std::sin(v), -std::sin(u) * std::cos(v));
      const glm::vec3 centre(major * std::cos(u), 0.0, -major * std::sin(u));
      torus.positions.push_back(centre + minor * normal);
      torus.normals.push_back(normal);
    }
  }
  const auto at = [&](int i, int j) {
    return static_cast<uint32_t>((i % rings) * sides + (j % sides));
  };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < sides; ++j) {
      torus.indices.insert(torus.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      torus.indices.insert(torus.indices.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return torus;
}

const Torus& torus() {
  static const Torus mesh = make_torus(140, 250, 1.0f, 0.4f);
  return mesh;
}

void run_frames(benchmark::State& state, std::span<const glm::dvec4> clip_planes) {
  const Torus& mesh = torus();
  soltex::RasterObject object;
  object.mesh = {mesh.positions, mesh.normals, mesh.indices};
  object.model = glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(1.0f, 0.0f, 0.0f));
  const glm::mat4 view_projection =
      glm::perspective(glm::radians(45.0f), static_cast<float>(kWidth) / kHeight, 0.1f, 100.0f) *
      glm::lookAt(glm::vec3(0.0f, 1.0f, 3.2f), glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  const soltex::RasterView view{kWidth, kHeight, view_projection, clip_planes};
  soltex::Rasterizer rasterizer({.threads = static_cast<int>(state.range(0))});
  soltex::GBuffer gbuffer;
  soltex::RasterStats stats;
  for (auto _ : state) {
    stats = rasterizer.render(view, std::span<const soltex::RasterObject>(&object, 1), gbuffer);
    benchmark::DoNotOptimize(gbuffer.depth.data());
  }
  state.counters["triangles"] = static_cast<double>(stats.triangles_in);
  state.counters["pixels_covered"] = static_cast<double>(stats.pixels_covered);
  state.counters["fragments"] = static_cast<double>(stats.fragments_rasterized);
  state.counters["cap_pixels"] = static_cast<double>(stats.cap_pixels);
  state.counters["Mtri/s"] = benchmark::Counter(static_cast<double>(stats.triangles_in) * 1e-6,
                                                benchmark::Counter::kIsIterationInvariantRate);
}

void BM_RasterFrame(benchmark::State& state) {
  run_frames(state, {});
}

void BM_RasterFrameCut(benchmark::State& state) {
  static const std::vector<glm::dvec4> planes = {{0.3, 0.0, -1.0, 0.0}};
  run_frames(state, planes);
}

void BM_RasterFrameSlab(benchmark::State& state) {
  static const std::vector<glm::dvec4> planes = {{0.3, 0.0, -1.0, 0.15}, {-0.3, 0.0, 1.0, 0.15}};
  run_frames(state, planes);
}

BENCHMARK(BM_RasterFrame)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_RasterFrameCut)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_RasterFrameSlab)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
