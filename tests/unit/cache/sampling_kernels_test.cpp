// The runtime-dispatched sampling kernels give the scalar bits on every target this CPU runs
// (Highway compiles each target; SetSupportedTargetsForTest makes HWY_DYNAMIC_DISPATCH choose
// each in turn), and the sampler's batch form gives what its per-point form gives.
#include "soltex/common/sampling_kernels.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "real_bricks.h"
#include "soltex/common/cached_brick.h"
#include "soltex/common/sample_split.h"
#include "soltex/common/texture_sampler.h"
#include "soltex/common/trilinear_u8_scalar.h"

namespace soltex {
namespace {

using testing::RealTexture;
using testing::spec_of;

uint32_t bits(float f) {
  return std::bit_cast<uint32_t>(f);
}

// Calls `check` once per target the CPU supports and this build generated, with dispatch
// pinned to it; restores normal dispatch afterwards. Returns the targets' names.
template <class Check>
std::vector<std::string> on_every_target(const Check& check) {
  std::vector<std::string> names;
  for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    names.emplace_back(hwy::TargetName(target));
    SCOPED_TRACE(names.back());
    check();
  }
  hwy::SetSupportedTargetsForTest(0);
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : " ") + name;
  ::testing::Test::RecordProperty("targets", list);
  return names;
}

// Points that exercise every branch of the split: inside, on the faces, outside, -0, NaN,
// infinities, huge and tiny values; then a batch of random ones. Not a multiple of any lane
// count, so the tail path runs too.
std::vector<glm::dvec3> split_points(const glm::dvec3& origin, const glm::dvec3& spacing) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<glm::dvec3> points = {origin,
                                    origin + 64.0 * spacing,
                                    origin - spacing,
                                    origin + 1e-300,
                                    glm::dvec3(nan, inf, -inf),
                                    glm::dvec3(1e300, -1e300, -0.0),
                                    glm::dvec3(origin.x, -0.0, nan),
                                    origin + 17.0 * spacing};
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> wide(-2.0, 3.0);
  for (int n = 0; n < 3001; ++n) points.emplace_back(wide(rng), wide(rng), wide(rng));
  return points;
}

TEST(SamplingKernels, SplitOnEveryTargetEqualsScalar) {
  const glm::dvec3 origin(-0.7, 0.3, 1.1);
  const glm::dvec3 spacing(1.3 / 64, 1.3 / 64, 1.3 / 64);
  const std::vector<glm::dvec3> points = split_points(origin, spacing);
  const std::vector<std::string> targets = on_every_target([&] {
    CellChunk chunk;
    for (int level = 0; level <= 3; ++level) {
      const double scale = std::ldexp(1.0, -level);
      const double cells = 64 >> level;
      for (std::size_t first = 0; first < points.size(); first += kSampleChunk) {
        const std::size_t n = std::min(kSampleChunk, points.size() - first);
        split_cells(std::span(points).subspan(first, n), origin, spacing, scale, cells, chunk);
        for (std::size_t i = 0; i < n; ++i) {
          const CellSplit slow =
              split_cell_scalar(points[first + i], origin, spacing, scale, cells);
          for (int a = 0; a < 3; ++a) {
            const auto axis = static_cast<std::size_t>(a);
            ASSERT_EQ(chunk.cell[axis][i], slow.cell[a]) << "point " << first + i;
            ASSERT_EQ(bits(chunk.frac[axis][i]), bits(slow.frac[a])) << "point " << first + i;
          }
        }
      }
    }
  });
  EXPECT_FALSE(targets.empty());
}

// Brick index and offset inside the brick, as the scalar arithmetic gives them, for bricks of 8
// and 16 and every channel count.
TEST(SamplingKernels, LocateOnEveryTargetEqualsScalar) {
  std::mt19937 rng(21);
  for (const int shift : {3, 4}) {
    for (int channels = 1; channels <= 5; ++channels) {
      const int samples = (1 << shift) + 1;
      const BrickGeometry g{shift,    (1 << shift) - 1,   64,
                            channels, samples * channels, samples * samples * channels};
      std::uniform_int_distribution<int32_t> cell(0, (64 << shift) - 1);
      CellChunk chunk;
      for (auto& axis : chunk.cell) {
        for (int32_t& c : axis) c = cell(rng);
      }
      chunk.cell[0][0] = 0;
      chunk.cell[1][1] = (64 << shift) - 1;
      on_every_target([&] {
        const std::size_t n = kSampleChunk - 3;
        locate_cells(chunk, n, g);
        for (std::size_t i = 0; i < n; ++i) {
          const int32_t x = chunk.cell[0][i], y = chunk.cell[1][i], z = chunk.cell[2][i];
          ASSERT_EQ(chunk.brick[i], ((z >> shift) * 64 + (y >> shift)) * 64 + (x >> shift)) << i;
          ASSERT_EQ(chunk.offset[i],
                    (z & g.mask) * g.z_stride + (y & g.mask) * g.y_stride + (x & g.mask) * channels)
              << i;
        }
      });
    }
  }
}

// Every cell of a brick with every byte value around it, fractions including 0 and 1: the
// three channels equal the scalar kernel's bits, the fourth float is +0, and a null corner
// leaves its output alone.
TEST(SamplingKernels, TrilinearRgbOnEveryTargetEqualsScalar) {
  constexpr int kB = 8;
  constexpr int kSamples = (kB + 1) * (kB + 1) * (kB + 1);
  std::vector<uint8_t> planar(static_cast<std::size_t>(3 * kSamples));
  std::mt19937 bytes(9);
  for (uint8_t& b : planar) b = static_cast<uint8_t>(bytes() & 0xFF);
  planar[0] = 255;
  planar[1] = 0;
  const CachedBrick brick(kB, 3, planar);

  std::mt19937 rng(3);
  std::uniform_int_distribution<int> cell(0, kB - 1);
  std::uniform_real_distribution<float> frac(0.0f, 1.0f);
  const std::vector<float> edges = {0.0f, 1.0f, 0.5f, std::nextafter(1.0f, 0.0f)};
  constexpr std::size_t kRounds = 40;
  std::vector<std::array<const uint8_t*, kSampleChunk>> corners(kRounds);
  std::vector<CellChunk> chunks(kRounds);
  for (std::size_t r = 0; r < kRounds; ++r) {
    for (std::size_t i = 0; i < kSampleChunk; ++i) {
      corners[r][i] = i % 13 == 5 ? nullptr : brick.sample(cell(rng), cell(rng), cell(rng));
      for (std::size_t a = 0; a < 3; ++a) {
        chunks[r].frac[a][i] = (i + a) % 7 == 0 ? edges[(i + r) % edges.size()] : frac(rng);
      }
    }
  }
  const float sentinel = -7.0f;
  on_every_target([&] {
    for (std::size_t r = 0; r < kRounds; ++r) {
      // An odd count: the last chunk of a batch is usually partial.
      const std::size_t n = r % 2 == 0 ? kSampleChunk : kSampleChunk - r;
      std::vector<float> out(kSampleChunk * 5, sentinel);
      trilinear_rgb(std::span<const uint8_t* const>(corners[r].data(), n), chunks[r],
                    brick.y_stride(), brick.z_stride(), out.data(), 5);
      for (std::size_t i = 0; i < kSampleChunk; ++i) {
        const float* got = &out[i * 5];
        if (i >= n || corners[r][i] == nullptr) {
          for (int c = 0; c < 5; ++c) ASSERT_EQ(bits(got[c]), bits(sentinel)) << i;
          continue;
        }
        float want[3];
        trilinear_detail::scalar<3>(corners[r][i], brick.y_stride(), brick.z_stride(),
                                    chunks[r].frac[0][i], chunks[r].frac[1][i],
                                    chunks[r].frac[2][i], want);
        for (int c = 0; c < 3; ++c) ASSERT_EQ(bits(got[c]), bits(want[c])) << i;
        ASSERT_EQ(bits(got[3]), 0u) << i;
        ASSERT_EQ(bits(got[4]), bits(sentinel)) << i;
      }
    }
  });
}

// The rows form over arbitrary row bytes (every byte value, the two padding bytes included),
// for every count up to a chunk: each of the first n outputs equals the scalar kernel over the
// same four rows, the fourth float is +0, and nothing past n is written, whatever the chunk's
// fractions past n hold (NaN here).
TEST(SamplingKernels, TrilinearRgbRowsOnEveryTargetEqualsScalar) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<float> frac(0.0f, 1.0f);
  CellRows rows;
  CellChunk chunk;
  for (std::size_t i = 0; i < kSampleChunk; ++i) {
    for (auto& row : rows.row) row[i] = rng();
    for (std::size_t a = 0; a < 3; ++a) chunk.frac[a][i] = i % 11 == 3 ? 1.0f : frac(rng);
  }
  rows.row[0][0] = ~uint64_t{0};
  const float sentinel = -7.0f;
  on_every_target([&] {
    for (std::size_t n = 1; n <= kSampleChunk; ++n) {
      CellChunk garbled = chunk;
      for (auto& axis : garbled.frac) {
        std::fill(axis.begin() + static_cast<std::ptrdiff_t>(n), axis.end(),
                  std::numeric_limits<float>::quiet_NaN());
      }
      std::vector<float> out(kSampleChunk * 5, sentinel);
      trilinear_rgb_rows(rows, garbled, n, out.data(), 5);
      for (std::size_t i = 0; i < kSampleChunk; ++i) {
        const float* got = &out[i * 5];
        if (i >= n) {
          for (int c = 0; c < 5; ++c) ASSERT_EQ(bits(got[c]), bits(sentinel)) << n << " " << i;
          continue;
        }
        uint8_t cell[32];
        for (std::size_t r = 0; r < 4; ++r) std::memcpy(cell + 8 * r, &rows.row[r][i], 8);
        float want[3];
        trilinear_detail::scalar<3>(cell, 8, 16, chunk.frac[0][i], chunk.frac[1][i],
                                    chunk.frac[2][i], want);
        for (int c = 0; c < 3; ++c) ASSERT_EQ(bits(got[c]), bits(want[c])) << n << " " << i;
        ASSERT_EQ(bits(got[3]), 0u) << n << " " << i;
        ASSERT_EQ(bits(got[4]), bits(sentinel)) << n << " " << i;
      }
    }
  });
}

Volume test_volume() {
  Volume volume;
  volume.min = glm::dvec3(-0.7, 0.3, 1.1);
  volume.max = volume.min + glm::dvec3(1.3);
  volume.finest_level_log2 = 5;
  return volume;
}

void expect_same(const SampleResult& batch, const SampleResult& point, std::size_t i) {
  for (std::size_t c = 0; c < batch.values.size(); ++c) {
    ASSERT_EQ(bits(batch.values[c]), bits(point.values[c])) << "point " << i << " channel " << c;
  }
  ASSERT_EQ(batch.level, point.level) << i;
  ASSERT_EQ(batch.complete, point.complete) << i;
}

// The batch form equals the per-point form bit for bit on every target, for every filter, a
// few levels of detail (NaN included), points outside the volume, and bricks missing (level 0
// is left out, so every trilinear lookup at level 0 falls back to level 1).
TEST(SamplingKernels, SamplerBatchEqualsPerPointOnEveryTarget) {
  for (const ChannelSet channels : {ChannelSet{}, ChannelSet{true, true, true}}) {
    const RealTexture texture(spec_of(MarbleParams{}, channels), test_volume(), 8);
    for (const bool with_level0 : {true, false}) {
      BrickCache cache(std::size_t{256} << 20);
      for (int level = with_level0 ? 0 : 1; level <= texture.layout.coarsest_level(); ++level) {
        texture.insert_level(cache, level);
      }
      std::mt19937_64 rng(17);
      std::uniform_real_distribution<double> coordinate(-1.0, 2.7);
      std::vector<glm::dvec3> points(1000);
      for (glm::dvec3& p : points)
        p = glm::dvec3(coordinate(rng), coordinate(rng), coordinate(rng));
      points[3] = glm::dvec3(std::numeric_limits<double>::quiet_NaN());
      on_every_target([&] {
        TextureSampler batch(cache, texture.id, texture.layout, texture.channels);
        TextureSampler single(cache, texture.id, texture.layout, texture.channels);
        for (const SampleFilter filter :
             {SampleFilter::trilinear, SampleFilter::nearest, SampleFilter::quadrilinear}) {
          for (const double lod : {0.0, 0.4, 1.0, 2.6, std::numeric_limits<double>::quiet_NaN()}) {
            std::vector<SampleResult> results(points.size());
            batch.sample(points, lod, filter, results);
            for (std::size_t i = 0; i < points.size(); ++i) {
              expect_same(results[i], single.sample(points[i], lod, filter), i);
            }
          }
        }
      });
    }
  }
}

// A batch of several chunks is located one chunk ahead of the one filtered. With every other
// level-0 brick resident, runs of hits and misses cross the chunks' ends; every batch size
// (none, under, at and past a chunk, several chunks and a partial one) still equals the
// per-point form bit for bit.
TEST(SamplingKernels, SamplerBatchOfChunksEqualsPerPointWithBricksMissing) {
  const RealTexture texture(spec_of(MarbleParams{}, ChannelSet{}), test_volume(), 8);
  BrickCache cache(std::size_t{256} << 20);
  const int bricks = texture.layout.bricks_per_axis(0);
  for (int z = 0; z < bricks; ++z) {
    for (int y = 0; y < bricks; ++y) {
      for (int x = 0; x < bricks; ++x) {
        if ((x + y + z) % 2 == 0) texture.insert(cache, 0, {x, y, z});
      }
    }
  }
  for (int level = 1; level <= texture.layout.coarsest_level(); ++level) {
    texture.insert_level(cache, level);
  }
  // Along a slanted line through the volume, as a row of pixels meets it: runs of a few dozen
  // points per brick.
  std::vector<glm::dvec3> points(1000);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(points.size());
    points[i] = glm::dvec3(-0.75 + 1.4 * t, 0.35 + 1.1 * t, 2.35 - 1.2 * t);
  }
  on_every_target([&] {
    TextureSampler batch(cache, texture.id, texture.layout, texture.channels);
    TextureSampler single(cache, texture.id, texture.layout, texture.channels);
    for (const std::size_t size :
         {std::size_t{0}, std::size_t{1}, kSampleChunk - 1, kSampleChunk, kSampleChunk + 1,
          kSampleBatch, kSampleBatch + 7, points.size()}) {
      for (const double lod : {0.0, 1.0}) {
        const std::span<const glm::dvec3> some(points.data(), size);
        std::vector<SampleResult> results(size);
        batch.sample(some, lod, SampleFilter::trilinear, results);
        std::size_t incomplete = 0;
        for (std::size_t i = 0; i < size; ++i) {
          expect_same(results[i], single.sample(points[i], lod, SampleFilter::trilinear), i);
          incomplete += results[i].complete ? 0 : 1;
        }
        // Level 0 misses half its bricks; level 1 has them all.
        if (lod == 0.0 && size == points.size()) {
          EXPECT_GT(incomplete, 0u);
          EXPECT_LT(incomplete, size);
        }
        if (lod == 1.0) {
          EXPECT_EQ(incomplete, 0u);
        }
      }
    }
  });
}

TEST(SamplingKernels, SamplerBatchChecksItsSizes) {
  const BrickLayout layout(test_volume(), 8);
  BrickCache cache(std::size_t{1} << 20);
  TextureSampler sampler(cache, 1, layout, 3);
  std::vector<glm::dvec3> points(3);
  std::vector<SampleResult> results(2);
  EXPECT_THROW(sampler.sample(points, 0.0, SampleFilter::trilinear, results),
               std::invalid_argument);
}

}  // namespace
}  // namespace soltex
