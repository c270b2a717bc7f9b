// Cached sampling against its alternatives, one thread, nanoseconds per RGB sample.
//
// The texture is 6-octave marble (MarbleParams defaults, value basis, RGB) in the unit cube,
// 2^8 = 256 cells per axis at level 0, bricks of B = 16. The points are 512 x 512 pixels of
// an oblique plane through the volume (about 0.4 voxels per pixel, so level 0 is the level a
// renderer would pick), visited in two orders:
//   *_Scanline  row after row, adjacent rows next to each other, as a rasterizer visits them;
//   *_Random    the same points shuffled.
// At every point, one image row (512 points) per call, into a row of SampleResults:
//   Cached_Trilinear     TextureSampler::sample(points, 0, trilinear, results): per chunk of
//                        64 points the runtime-dispatched cell split and brick location
//                        (sampling_kernels.h), one brick lookup per run of points in one
//                        brick (the sampler's last brick, its brick table, the accessor's
//                        microcache table, the sharded map), the dispatched RGB kernel;
//   Cached_Quadrilinear  the same at level of detail 0.5 (levels 0 and 1 blended; this
//                        filter goes point by point);
//   Dense_Trilinear      a dense 257^3 RGB uint8 array holding the same quantized voxels
//                        (the vertex-centred lattice of 256^3 cells, 48.6 MiB), through the
//                        same dispatched kernels (the whole lattice as one brick), filling
//                        the same SampleResults;
//   CachedPoint_*, DensePoint_*  the per-point forms (TextureSampler::sample(p, ...), and
//                        split_cell plus trilinear_u8 for the array): the build's static
//                        target, scalar in a generic build;
//   Marble_Direct        TextureEvaluator::sample of the marble, band-limited to level 0's
//                        spacing, at the same points: what the cache saves.
// The cache holds every level-0 and level-1 brick the plane touches (its budget is larger
// than they need, so nothing is evicted while measuring).
//
// OpenVDB's tree with a cached accessor would be a natural third comparison; it is optional
// (libopenvdb-dev) and not used here.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <random>
#include <set>
#include <span>
#include <tuple>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_layout.h"
#include "soltex/common/sample_split.h"
#include "soltex/common/sampling_kernels.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/texture_id.h"
#include "soltex/common/texture_sampler.h"
#include "soltex/common/texture_spec.h"
#include "soltex/common/trilinear_u8.h"

namespace {

constexpr int kFinestLevelLog2 = 8;
constexpr int kBrickSize = 16;
constexpr int kImageSide = 512;
constexpr std::size_t kPoints = static_cast<std::size_t>(kImageSide) * kImageSide;

// The same voxels as level 0 of the cache, as one RGB array, x fastest.
class DenseVolume {
 public:
  DenseVolume(const soltex::TextureEvaluator& texture, const soltex::BrickLayout& layout)
      : cells_(layout.cells_per_axis(0)),
        n_(layout.cells_per_axis(0) + 1),
        min_(layout.volume().min),
        spacing_(layout.spacing(0)),
        rgb_(static_cast<std::size_t>(n_) * n_ * n_ * 3 + soltex::kTrilinearLoadPadding) {
    // One z slab at a time: positions from global lattice indices, as the bricks have them,
    // so the voxels are bit-identical to the bricks'.
    soltex::Grid slab;
    slab.origin = min_;
    slab.step = spacing_;
    slab.count = glm::ivec3(n_, n_, 1);
    std::vector<float> planes(slab.size() * 3);
    const std::size_t plane = slab.size();
    for (int k = 0; k < n_; ++k) {
      slab.first = glm::ivec3(0, 0, k);
      texture.evaluate_grid(slab, layout.filter_width(0), planes);
      const std::vector<uint8_t> q = soltex::quantize(planes);
      uint8_t* out = rgb_.data() + static_cast<std::size_t>(k) * plane * 3;
      for (std::size_t i = 0; i < plane; ++i) {
        for (std::size_t c = 0; c < 3; ++c) *out++ = q[c * plane + i];
      }
    }
  }

  uint8_t at(int x, int y, int z, int c) const {
    return rgb_[((static_cast<std::size_t>(z) * n_ + y) * n_ + x) * 3 + c];
  }

  // The cache's clamping and cell split (soltex::split_cell), then the same kernel.
  void trilinear(const glm::dvec3& p, float* out) const {
    const soltex::CellSplit s = soltex::split_cell(p, min_, spacing_, 1.0, cells_);
    const uint8_t* corner =
        rgb_.data() + ((static_cast<std::size_t>(s.cell.z) * n_ + s.cell.y) * n_ + s.cell.x) * 3;
    soltex::trilinear_u8<3>(corner, static_cast<std::ptrdiff_t>(n_) * 3,
                            static_cast<std::ptrdiff_t>(n_) * n_ * 3, s.frac.x, s.frac.y, s.frac.z,
                            out);
  }

  // The same for a batch, in the shape of TextureSampler::sample(points, lod, filter,
  // results): the cell split and the kernel through the runtime-dispatched batch kernels, one
  // chunk at a time, into SampleResults (level 0, complete) as the sampler fills them.
  void trilinear(std::span<const glm::dvec3> points,
                 std::span<soltex::SampleResult> results) const {
    soltex::CellChunk chunk;
    std::array<const uint8_t*, soltex::kSampleChunk> corners;
    const auto y_stride = static_cast<std::ptrdiff_t>(n_) * 3;
    const auto z_stride = static_cast<std::ptrdiff_t>(n_) * n_ * 3;
    for (std::size_t first = 0; first < points.size(); first += soltex::kSampleChunk) {
      const std::size_t n = std::min(soltex::kSampleChunk, points.size() - first);
      soltex::split_cells(points.subspan(first, n), min_, spacing_, 1.0, cells_, chunk);
      // The whole lattice as one brick: the offsets are the indices.
      soltex::locate_cells(chunk, n, {31, INT32_MAX, 1, 3, y_stride, z_stride});
      for (std::size_t i = 0; i < n; ++i) corners[i] = rgb_.data() + chunk.offset[i];
      for (std::size_t i = 0; i < n; ++i) {
        soltex::SampleResult& result = results[first + i];
        result.values[4] = 0.0f;
        result.level = 0;
        result.complete = true;
      }
      soltex::trilinear_rgb(std::span<const uint8_t* const>(corners.data(), n), chunk, y_stride,
                            z_stride, results[first].values.data(),
                            sizeof(soltex::SampleResult) / sizeof(float));
    }
  }

  std::size_t bytes() const { return rgb_.size(); }

 private:
  double cells_;
  int n_;
  glm::dvec3 min_;
  glm::dvec3 spacing_;
  std::vector<uint8_t> rgb_;
};

struct Scene {
  Scene()
      : spec(make_spec()),
        volume(make_volume()),
        texture(spec),
        layout(volume, kBrickSize),
        id(soltex::texture_id(spec, volume, kBrickSize)),
        dense(texture, layout),
        cache(std::size_t{256} << 20) {
    // An oblique plane through the centre, spanned by two orthogonal directions.
    const glm::dvec3 centre(0.5, 0.5, 0.5);
    const glm::dvec3 a = glm::normalize(glm::dvec3(1.0, 0.35, 0.2)) * 0.85;
    glm::dvec3 b = glm::dvec3(-0.3, 1.0, 0.55);
    b = glm::normalize(b - glm::dot(b, a) / glm::dot(a, a) * a) * 0.85;
    scanline.reserve(kPoints);
    for (int y = 0; y < kImageSide; ++y) {
      for (int x = 0; x < kImageSide; ++x) {
        const double s = (x + 0.5) / kImageSide - 0.5;
        const double t = (y + 0.5) / kImageSide - 0.5;
        scanline.push_back(centre + s * a + t * b);
      }
    }
    random = scanline;
    std::shuffle(random.begin(), random.end(), std::mt19937_64(12345));
    fill_cache();
  }

  static soltex::TextureSpec make_spec() {
    soltex::TextureSpec s;
    s.pattern = soltex::MarbleParams{};  // turbulence octaves 0..5: six
    return s;
  }
  static soltex::Volume make_volume() {
    soltex::Volume v;
    v.finest_level_log2 = kFinestLevelLog2;
    return v;
  }

  // Every brick of levels 0 and 1 the plane touches, cut from the dense lattice at level 0
  // (the same voxels) and evaluated at level 1.
  void fill_cache() {
    soltex::TextureSampler locator(cache, id, layout, 3);
    for (int level = 0; level <= 1; ++level) {
      std::set<std::tuple<int, int, int>> touched;
      for (const glm::dvec3& p : scanline) {
        const soltex::BrickKey key = locator.brick_key(p, level);
        touched.emplace(key.brick.x, key.brick.y, key.brick.z);
      }
      for (const auto& [bx, by, bz] : touched) {
        const glm::ivec3 brick(bx, by, bz);
        std::vector<uint8_t> planar;
        if (level == 0) {
          planar = cut_level0(brick);
        } else {
          std::vector<float> samples(static_cast<std::size_t>(layout.samples_per_brick()) * 3);
          texture.evaluate_grid(layout.sample_grid(level, brick), layout.filter_width(level),
                                samples);
          planar = soltex::quantize(samples);
        }
        cache.insert(soltex::BrickKey{id, level, brick}, kBrickSize, 3, planar);
      }
      bricks[level] = touched.size();
    }
  }

  std::vector<uint8_t> cut_level0(const glm::ivec3& brick) const {
    const int n = kBrickSize + 1;
    const std::size_t plane = static_cast<std::size_t>(n) * n * n;
    std::vector<uint8_t> planar(plane * 3);
    std::size_t i = 0;
    for (int z = 0; z < n; ++z) {
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x, ++i) {
          const glm::ivec3 g = brick * kBrickSize + glm::ivec3(x, y, z);
          for (int c = 0; c < 3; ++c) planar[c * plane + i] = dense.at(g.x, g.y, g.z, c);
        }
      }
    }
    return planar;
  }

  soltex::TextureSpec spec;
  soltex::Volume volume;
  soltex::TextureEvaluator texture;
  soltex::BrickLayout layout;
  uint64_t id;
  DenseVolume dense;
  soltex::BrickCache cache;
  std::vector<glm::dvec3> scanline;
  std::vector<glm::dvec3> random;
  std::size_t bricks[2] = {0, 0};
};

Scene& scene() {
  static Scene s;
  return s;
}

const std::vector<glm::dvec3>& points_in(bool random_order) {
  return random_order ? scene().random : scene().scanline;
}

void report_samples(benchmark::State& state) {
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(kPoints));
  // Seconds per sample inverted; the 1e-9 factor makes it nanoseconds (the console reporter
  // prints it with an "s" suffix).
  state.counters["ns_per_sample"] = benchmark::Counter(
      static_cast<double>(kPoints) * 1e-9,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// What both cached forms report once their loop is done: a miss fails the run (the plane must
// be resident), then samples per second and the microcache's share of the lookups.
soltex::BrickCacheStats report_cached(benchmark::State& state, Scene& s,
                                      soltex::TextureSampler& sampler,
                                      const soltex::BrickCacheStats& before, bool complete) {
  sampler.flush_statistics();
  const soltex::BrickCacheStats after = s.cache.stats();
  if (!complete) state.SkipWithError("a lookup missed: the cache does not hold the plane");
  report_samples(state);
  state.counters["microcache_hit_rate"] =
      static_cast<double>(after.microcache_hits - before.microcache_hits) /
      static_cast<double>(std::max<uint64_t>(1, after.lookups - before.lookups));
  return after;
}

void BM_CachedPoint(benchmark::State& state, bool random_order, double lod,
                    soltex::SampleFilter filter) {
  Scene& s = scene();
  const std::vector<glm::dvec3>& points = points_in(random_order);
  soltex::TextureSampler sampler(s.cache, s.id, s.layout, 3);
  const soltex::BrickCacheStats before = s.cache.stats();
  bool complete = true;
  for (auto _ : state) {
    float sink = 0.0f;
    for (const glm::dvec3& p : points) {
      const soltex::SampleResult r = sampler.sample(p, lod, filter);
      complete = complete && r.complete;
      sink += r.values[0] + r.values[1] + r.values[2];
    }
    benchmark::DoNotOptimize(sink);
  }
  const soltex::BrickCacheStats after = report_cached(state, s, sampler, before, complete);
  state.counters["bricks_l0"] = static_cast<double>(s.bricks[0]);
  state.counters["cache_MiB"] = static_cast<double>(after.resident_bytes) / (1 << 20);
}

void BM_DensePoint(benchmark::State& state, bool random_order) {
  const DenseVolume& dense = scene().dense;
  const std::vector<glm::dvec3>& points = points_in(random_order);
  for (auto _ : state) {
    float sink = 0.0f;
    for (const glm::dvec3& p : points) {
      float rgb[4];
      dense.trilinear(p, rgb);
      sink += rgb[0] + rgb[1] + rgb[2];
    }
    benchmark::DoNotOptimize(sink);
  }
  report_samples(state);
  state.counters["array_MiB"] = static_cast<double>(dense.bytes()) / (1 << 20);
}

// The batch forms: one image row (kImageSide points) per call, as a renderer hands over a
// row of a tile, into a reused row of results.
void BM_Cached(benchmark::State& state, bool random_order, double lod,
               soltex::SampleFilter filter) {
  Scene& s = scene();
  const std::span<const glm::dvec3> points = points_in(random_order);
  soltex::TextureSampler sampler(s.cache, s.id, s.layout, 3);
  std::vector<soltex::SampleResult> row(kImageSide);
  const soltex::BrickCacheStats before = s.cache.stats();
  bool complete = true;
  for (auto _ : state) {
    float sink = 0.0f;
    for (std::size_t first = 0; first < points.size(); first += kImageSide) {
      sampler.sample(points.subspan(first, kImageSide), lod, filter, row);
      for (const soltex::SampleResult& r : row) {
        complete = complete && r.complete;
        sink += r.values[0] + r.values[1] + r.values[2];
      }
    }
    benchmark::DoNotOptimize(sink);
  }
  report_cached(state, s, sampler, before, complete);
}

void BM_Dense(benchmark::State& state, bool random_order) {
  const DenseVolume& dense = scene().dense;
  const std::span<const glm::dvec3> points = points_in(random_order);
  std::vector<soltex::SampleResult> row(kImageSide);
  bool complete = true;
  for (auto _ : state) {
    float sink = 0.0f;
    for (std::size_t first = 0; first < points.size(); first += kImageSide) {
      dense.trilinear(points.subspan(first, kImageSide), row);
      for (const soltex::SampleResult& r : row) {
        complete = complete && r.complete;
        sink += r.values[0] + r.values[1] + r.values[2];
      }
    }
    benchmark::DoNotOptimize(sink);
  }
  benchmark::DoNotOptimize(complete);
  report_samples(state);
}

void BM_Marble(benchmark::State& state, bool random_order) {
  Scene& s = scene();
  const std::vector<glm::dvec3>& points = points_in(random_order);
  const double width = s.layout.filter_width(0);
  for (auto _ : state) {
    float sink = 0.0f;
    for (const glm::dvec3& p : points) {
      const soltex::Texel t = s.texture.sample(p, width);
      sink += t.colour.r + t.colour.g + t.colour.b;
    }
    benchmark::DoNotOptimize(sink);
  }
  report_samples(state);
}

using soltex::SampleFilter;
BENCHMARK_CAPTURE(BM_Cached, Trilinear_Scanline, false, 0.0, SampleFilter::trilinear)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Dense, Trilinear_Scanline, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Cached, Trilinear_Random, true, 0.0, SampleFilter::trilinear)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Dense, Trilinear_Random, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CachedPoint, Trilinear_Scanline, false, 0.0, SampleFilter::trilinear)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DensePoint, Trilinear_Scanline, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CachedPoint, Trilinear_Random, true, 0.0, SampleFilter::trilinear)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DensePoint, Trilinear_Random, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Marble, Direct_Scanline, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Marble, Direct_Random, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Cached, Quadrilinear_Scanline, false, 0.5, SampleFilter::quadrilinear)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Cached, Quadrilinear_Random, true, 0.5, SampleFilter::quadrilinear)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
