#include "soltex/common/brick_cache.h"

#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

#include "real_bricks.h"
#include "soltex/common/cached_brick.h"
#include "soltex/common/texture_sampler.h"
#include "soltex/common/trilinear_u8.h"

namespace soltex {
namespace {

using testing::RealTexture;
using testing::spec_of;

constexpr int kB = 8;
constexpr int kSamples = (kB + 1) * (kB + 1) * (kB + 1);

// A synthetic planar brick: sample (i, channel c) = (i * 7 + c * 31 + seed) mod 256.
std::vector<uint8_t> synthetic_planar(int channels, int seed = 0) {
  std::vector<uint8_t> planar(static_cast<std::size_t>(kSamples * channels));
  for (int c = 0; c < channels; ++c) {
    for (int i = 0; i < kSamples; ++i) {
      planar[static_cast<std::size_t>(c * kSamples + i)] =
          static_cast<uint8_t>((i * 7 + c * 31 + seed) & 0xFF);
    }
  }
  return planar;
}

BrickKey key_of(int n, int level = 0) {
  return BrickKey{42, level, glm::ivec3(n, 0, 0)};
}

bool insert_synthetic(BrickCache& cache, const BrickKey& key, int channels = 3) {
  return cache.insert(key, kB, channels, synthetic_planar(channels, key.brick.x));
}

TEST(CachedBrick, StoresPlanarSamplesInterleaved) {
  for (int channels = 1; channels <= CachedBrick::kMaxChannels; ++channels) {
    const std::vector<uint8_t> planar = synthetic_planar(channels);
    const CachedBrick brick(kB, channels, planar);
    EXPECT_EQ(brick.channels(), channels);
    EXPECT_EQ(brick.y_stride(), (kB + 1) * channels);
    EXPECT_EQ(brick.z_stride(), (kB + 1) * (kB + 1) * channels);
    EXPECT_EQ(brick.sample_bytes(),
              static_cast<std::size_t>(kSamples * channels) + kTrilinearLoadPadding);
    for (int z = 0; z <= kB; ++z) {
      for (int y = 0; y <= kB; ++y) {
        for (int x = 0; x <= kB; ++x) {
          const int i = (z * (kB + 1) + y) * (kB + 1) + x;
          for (int c = 0; c < channels; ++c) {
            ASSERT_EQ(brick.at(x, y, z, c), planar[static_cast<std::size_t>(c * kSamples + i)]);
          }
        }
      }
    }
    // At a corner, trilinear returns the corner sample.
    float out[CachedBrick::kMaxChannels];
    brick.trilinear({kB - 1, kB - 1, kB - 1}, {1.0f, 1.0f, 1.0f}, out);
    for (int c = 0; c < channels; ++c) {
      EXPECT_EQ(out[c], static_cast<float>(brick.at(kB, kB, kB, c)) * (1.0f / 255.0f));
    }
  }
}

TEST(CachedBrick, RejectsMalformedInput) {
  const std::vector<uint8_t> planar = synthetic_planar(3);
  EXPECT_THROW(CachedBrick(4, 3, planar), std::invalid_argument);
  EXPECT_THROW(CachedBrick(kB, 0, {}), std::invalid_argument);
  EXPECT_THROW(CachedBrick(kB, 6, planar), std::invalid_argument);
  EXPECT_THROW(CachedBrick(kB, 4, planar), std::invalid_argument);
  EXPECT_THROW(CachedBrick(16, 3, planar), std::invalid_argument);
}

// The per-sample kernel, compiled for the build's static Highway target (SIMD where the
// compiler flags allow it), does the scalar kernel's operations in the same order. The batch
// kernels are checked on every runtime-dispatched target in sampling_kernels_test.cpp.
template <int Channels>
void expect_static_target_equals_scalar() {
  const std::vector<uint8_t> planar = synthetic_planar(Channels, 5);
  const CachedBrick brick(kB, Channels, planar);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> cell(0, kB - 1);
  std::uniform_real_distribution<float> frac(0.0f, 1.0f);
  for (int n = 0; n < 2000; ++n) {
    const uint8_t* s = brick.sample(cell(rng), cell(rng), cell(rng));
    const float fx = frac(rng), fy = frac(rng), fz = frac(rng);
    float fast[4] = {}, slow[4] = {};
    trilinear_detail::scalar<Channels>(s, brick.y_stride(), brick.z_stride(), fx, fy, fz, slow);
    trilinear_u8<Channels>(s, brick.y_stride(), brick.z_stride(), fx, fy, fz, fast);
    for (int c = 0; c < 4; ++c) {
      ASSERT_EQ(std::bit_cast<uint32_t>(fast[c]), std::bit_cast<uint32_t>(slow[c]))
          << "channel " << c << " of " << Channels;
    }
  }
}

TEST(TrilinearU8, StaticTargetEqualsScalarBitForBit) {
  expect_static_target_equals_scalar<3>();
  expect_static_target_equals_scalar<4>();
}

TEST(BrickCache, FindsWhatWasInsertedAndCountsLookups) {
  BrickCache cache(1 << 20);
  ASSERT_TRUE(insert_synthetic(cache, key_of(1)));
  EXPECT_TRUE(cache.contains(key_of(1)));
  EXPECT_FALSE(cache.contains(key_of(2)));
  const auto handle = cache.find(key_of(1));
  ASSERT_NE(handle, nullptr);
  EXPECT_EQ(handle->at(0, 0, 0, 1), 32);  // 0 * 7 + 1 * 31 + seed 1
  EXPECT_EQ(cache.find(key_of(2)), nullptr);
  {
    BrickCache::Accessor accessor(cache);
    for (int i = 0; i < 10; ++i) ASSERT_NE(accessor.find(key_of(1)), nullptr);
    EXPECT_EQ(accessor.find(key_of(3)), nullptr);
  }  // flushes its counts
  const BrickCacheStats s = cache.stats();
  EXPECT_EQ(s.lookups, 13u);
  EXPECT_EQ(s.hits, 11u);
  EXPECT_EQ(s.microcache_hits, 9u);
  EXPECT_EQ(s.misses, 2u);
  EXPECT_EQ(s.lookups, s.hits + s.misses);
  EXPECT_EQ(s.insertions, 1u);
  EXPECT_EQ(s.resident_bricks, 1u);
  EXPECT_EQ(s.resident_bytes, BrickCache::charged_bytes(kB, 3));
}

TEST(BrickCache, ChargesSamplesAndBookkeeping) {
  EXPECT_GT(BrickCache::charged_bytes(kB, 3), CachedBrick::sample_bytes(kB, 3));
  EXPECT_GT(BrickCache::charged_bytes(16, 3), BrickCache::charged_bytes(kB, 3));
  EXPECT_GT(BrickCache::charged_bytes(kB, 5), BrickCache::charged_bytes(kB, 3));
}

TEST(BrickCache, InsertingAResidentKeyKeepsIt) {
  BrickCache cache(1 << 20);
  ASSERT_TRUE(insert_synthetic(cache, key_of(1)));
  ASSERT_TRUE(insert_synthetic(cache, key_of(1)));
  const BrickCacheStats s = cache.stats();
  EXPECT_EQ(s.insertions, 1u);
  EXPECT_EQ(s.resident_bricks, 1u);
  EXPECT_EQ(s.resident_bytes, BrickCache::charged_bytes(kB, 3));
}

TEST(BrickCache, NeverExceedsItsBudget) {
  const std::size_t brick = BrickCache::charged_bytes(kB, 3);
  const std::size_t budget = 10 * brick + brick / 2;
  BrickCache cache(budget);
  for (int n = 0; n < 200; ++n) {
    ASSERT_TRUE(insert_synthetic(cache, key_of(n)));
    const BrickCacheStats s = cache.stats();
    ASSERT_LE(s.resident_bytes, budget);
    ASSERT_EQ(s.resident_bytes, s.resident_bricks * brick);
    if (n % 7 == 0) cache.begin_frame();
  }
  const BrickCacheStats s = cache.stats();
  EXPECT_EQ(s.resident_bricks, 10u);
  EXPECT_EQ(s.evictions, 190u);
  EXPECT_EQ(s.insertions, 200u);
  EXPECT_LE(s.peak_resident_bytes, budget);
  EXPECT_TRUE(cache.contains(key_of(199)));
}

TEST(BrickCache, RefusesABrickLargerThanTheBudget) {
  BrickCache cache(BrickCache::charged_bytes(kB, 3) - 1);
  EXPECT_FALSE(insert_synthetic(cache, key_of(0)));
  EXPECT_EQ(cache.stats().refused_insertions, 1u);
  EXPECT_EQ(cache.stats().resident_bytes, 0u);
}

TEST(BrickCache, BricksHitThisFrameAreNotEvicted) {
  const std::size_t budget = 4 * BrickCache::charged_bytes(kB, 3);
  BrickCache cache(budget);
  for (int n = 0; n < 4; ++n) ASSERT_TRUE(insert_synthetic(cache, key_of(n)));
  cache.begin_frame();
  BrickCache::Accessor accessor(cache);
  ASSERT_NE(accessor.find(key_of(2)), nullptr);  // pinned for this frame
  for (int n = 4; n < 40; ++n) {
    ASSERT_TRUE(insert_synthetic(cache, key_of(n)));
    ASSERT_TRUE(cache.contains(key_of(2))) << "after inserting " << n;
  }
  // In a new frame it is evictable again.
  cache.begin_frame();
  for (int n = 40; n < 80; ++n) ASSERT_TRUE(insert_synthetic(cache, key_of(n)));
  EXPECT_FALSE(cache.contains(key_of(2)));
  EXPECT_LE(cache.stats().resident_bytes, budget);
}

TEST(BrickCache, PinnedLevelsAreNeverEvicted) {
  const std::size_t budget = 5 * BrickCache::charged_bytes(kB, 3);
  BrickCache cache(budget);
  cache.pin_levels(42, 3);
  ASSERT_TRUE(insert_synthetic(cache, key_of(0, 3)));
  ASSERT_TRUE(insert_synthetic(cache, key_of(1, 4)));
  for (int n = 0; n < 50; ++n) {
    ASSERT_TRUE(insert_synthetic(cache, key_of(n, n % 3)));
    cache.begin_frame();
  }
  EXPECT_TRUE(cache.contains(key_of(0, 3)));
  EXPECT_TRUE(cache.contains(key_of(1, 4)));
  // Another texture's level 3 is not pinned.
  ASSERT_TRUE(insert_synthetic(cache, BrickKey{7, 3, glm::ivec3(0)}));
  for (int n = 50; n < 60; ++n) ASSERT_TRUE(insert_synthetic(cache, key_of(n, 0)));
  EXPECT_FALSE(cache.contains(BrickKey{7, 3, glm::ivec3(0)}));
  // Unpinning makes them evictable.
  cache.pin_levels(42, 100);
  for (int n = 60; n < 80; ++n) ASSERT_TRUE(insert_synthetic(cache, key_of(n, 0)));
  EXPECT_FALSE(cache.contains(key_of(0, 3)));
  EXPECT_LE(cache.stats().peak_resident_bytes, budget);
}

TEST(BrickCache, RefusesInsertionWhenEverythingIsPinned) {
  const std::size_t budget = 3 * BrickCache::charged_bytes(kB, 3);
  BrickCache cache(budget);
  for (int n = 0; n < 3; ++n) ASSERT_TRUE(insert_synthetic(cache, key_of(n)));
  cache.begin_frame();
  for (int n = 0; n < 3; ++n) ASSERT_NE(cache.find(key_of(n)), nullptr);
  EXPECT_FALSE(insert_synthetic(cache, key_of(3)));
  BrickCacheStats s = cache.stats();
  EXPECT_EQ(s.refused_insertions, 1u);
  EXPECT_EQ(s.resident_bricks, 3u);
  EXPECT_LE(s.resident_bytes, budget);
  for (int n = 0; n < 3; ++n) EXPECT_TRUE(cache.contains(key_of(n)));
  cache.begin_frame();
  EXPECT_TRUE(insert_synthetic(cache, key_of(3)));
  s = cache.stats();
  EXPECT_EQ(s.resident_bricks, 3u);
  EXPECT_EQ(s.evictions, 1u);
}

TEST(BrickCache, AccessorKeepsAHandedOutBrickReadableButDoesNotFindItOnceEvicted) {
  const std::size_t budget = 2 * BrickCache::charged_bytes(kB, 3);
  BrickCache cache(budget);
  ASSERT_TRUE(insert_synthetic(cache, key_of(0)));
  ASSERT_TRUE(insert_synthetic(cache, key_of(1)));
  BrickCache::Accessor accessor(cache);
  ASSERT_NE(accessor.find(key_of(1)), nullptr);
  const CachedBrick* first = accessor.find(key_of(0));
  ASSERT_NE(first, nullptr);
  cache.begin_frame();
  for (int n = 2; n < 6; ++n) ASSERT_TRUE(insert_synthetic(cache, key_of(n)));
  ASSERT_FALSE(cache.contains(key_of(0)));
  ASSERT_FALSE(cache.contains(key_of(1)));
  // Valid until the accessor's next find(): the accessor holds it (ASan would catch a use
  // after free)...
  EXPECT_EQ(first->at(1, 0, 0, 0), 7);
  EXPECT_EQ(first->at(0, 0, 0, 0), 0);
  // ...but it is no longer found, although the microcache held both.
  EXPECT_EQ(accessor.find(key_of(0)), nullptr);
  EXPECT_EQ(accessor.find(key_of(1)), nullptr);
  EXPECT_NE(accessor.find(key_of(5)), nullptr);
  accessor.flush_statistics();
  EXPECT_EQ(cache.stats().misses, 2u);
}

TEST(BrickCache, AccessorRemembersManyBricks) {
  BrickCache cache(std::size_t{64} << 20);
  constexpr int kBricks = 64;
  for (int n = 0; n < kBricks; ++n) ASSERT_TRUE(insert_synthetic(cache, key_of(n)));
  BrickCache::Accessor accessor(cache);
  for (int round = 0; round < 3; ++round) {
    for (int n = 0; n < kBricks; ++n) {
      const CachedBrick* brick = accessor.find(key_of(n));
      ASSERT_NE(brick, nullptr);
      ASSERT_EQ(brick->at(0, 0, 0, 0), n & 0xFF);  // the right brick, also from the table
    }
  }
  accessor.flush_statistics();
  const BrickCacheStats s = cache.stats();
  EXPECT_EQ(s.hits, 3u * kBricks);
  // The first round fills the table; the later ones find every brick there.
  EXPECT_EQ(s.microcache_hits, 2u * kBricks);
}

// Small bricks get a larger table (a frame touches more of them), within a bound on the
// evicted bytes an accessor may keep alive.
TEST(BrickCache, AccessorTableGrowsForSmallBricks) {
  EXPECT_EQ(BrickCache::Accessor::set_bits_for(16, 3), BrickCache::Accessor::kMinSetBits);
  EXPECT_EQ(BrickCache::Accessor::set_bits_for(8, 3), BrickCache::Accessor::kMaxSetBits);
  for (const int size : {8, 16}) {
    for (int channels = 1; channels <= CachedBrick::kMaxChannels; ++channels) {
      const int bits = BrickCache::Accessor::set_bits_for(size, channels);
      const std::size_t slots = BrickCache::Accessor::kWays << bits;
      if (bits > BrickCache::Accessor::kMinSetBits) {
        EXPECT_LE(slots * BrickCache::charged_bytes(size, channels),
                  BrickCache::Accessor::kRetainedBytes);
      }
    }
  }
  // A 2,048-slot table remembers more bricks from one round to the next than 512 slots could.
  BrickCache cache(std::size_t{256} << 20);
  constexpr int kBricks = 1024;
  for (int n = 0; n < kBricks; ++n) ASSERT_TRUE(insert_synthetic(cache, key_of(n)));
  BrickCache::Accessor accessor(cache, BrickCache::Accessor::kMaxSetBits);
  EXPECT_EQ(accessor.sets(), std::size_t{1} << BrickCache::Accessor::kMaxSetBits);
  for (int round = 0; round < 2; ++round) {
    for (int n = 0; n < kBricks; ++n) ASSERT_NE(accessor.find(key_of(n)), nullptr);
  }
  accessor.flush_statistics();
  EXPECT_GT(cache.stats().microcache_hits, 512u);
}

TEST(BrickCache, AccessorMicrocacheHoldsTwoBricks) {
  BrickCache cache(1 << 20);
  for (int n = 0; n < 3; ++n) ASSERT_TRUE(insert_synthetic(cache, key_of(n)));
  {
    BrickCache::Accessor accessor(cache);
    const CachedBrick* a = accessor.find(key_of(0));
    const CachedBrick* b = accessor.find(key_of(1));
    for (int i = 0; i < 5; ++i) {  // alternating between two bricks stays in the microcache
      ASSERT_EQ(accessor.find(key_of(0)), a);
      ASSERT_EQ(accessor.find(key_of(1)), b);
    }
    accessor.flush_statistics();
    EXPECT_EQ(cache.stats().microcache_hits, 10u);
    ASSERT_NE(accessor.find(key_of(2)), nullptr);
    accessor.flush_statistics();
    EXPECT_EQ(cache.stats().microcache_hits, 10u);
    EXPECT_EQ(cache.stats().hits, 13u);
  }
}

// Two render threads sample while a third inserts (evicting) and advances frames. Every
// sample must be a valid value of the level it reports, never garbage: the colour cube's
// channels are known everywhere (see texture_sampler_test.cpp for the bound h / P).
TEST(BrickCache, ConcurrentSamplingWhileInsertingAndEvicting) {
  constexpr double kPeriod = 0.7;
  Volume volume;
  volume.finest_level_log2 = 6;  // levels 0..3 with B = 8
  const RealTexture texture(spec_of(ColourCubeParams{kPeriod}), volume, kB);
  const BrickLayout& layout = texture.layout;
  const int coarsest = layout.coarsest_level();

  // Every brick of levels 0..2, made up front so the writer only inserts.
  struct Made {
    BrickKey key;
    std::vector<uint8_t> planar;
  };
  std::vector<Made> bricks;
  for (int level = 0; level < coarsest; ++level) {
    const int n = layout.bricks_per_axis(level);
    for (int z = 0; z < n; ++z) {
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
          bricks.push_back({texture.key(level, {x, y, z}), texture.brick(level, {x, y, z})});
        }
      }
    }
  }

  const std::size_t budget = 40 * BrickCache::charged_bytes(kB, 3);
  BrickCache cache(budget);
  cache.pin_levels(texture.id, coarsest);
  ASSERT_TRUE(texture.insert(cache, coarsest, {0, 0, 0}));

  std::atomic<bool> failed{false};
  const auto reader = [&](unsigned seed) {
    TextureSampler sampler(cache, texture.id, layout, texture.channels);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::uniform_real_distribution<double> lod(0.0, coarsest);
    MissedBricks missed;
    for (int n = 0; n < 50000 && !failed; ++n) {
      const glm::dvec3 p(unit(rng), unit(rng), unit(rng));
      const auto filter = static_cast<SampleFilter>(n % 3);
      const SampleResult r = sampler.sample(p, lod(rng), filter, &missed);
      // Quadrilinear may blend in a level up to the coarsest.
      const int worst_level = filter == SampleFilter::quadrilinear ? coarsest : r.level;
      const double bound = layout.filter_width(worst_level) / kPeriod + 0.5 / 255.0 + 1e-5;
      const std::vector<float> direct = texture.direct(p, 0);
      bool ok = r.level >= 0;
      for (std::size_t c = 0; c < 3; ++c) ok = ok && std::fabs(r.values[c] - direct[c]) <= bound;
      if (!ok) failed = true;
    }
  };
  std::atomic<bool> readers_done{false};
  std::atomic<int> inserted{0};
  const auto writer = [&] {
    std::mt19937_64 rng(99);
    std::uniform_int_distribution<std::size_t> pick(0, bricks.size() - 1);
    // Until the readers finish (bounded, should they hang), so they always race with it.
    for (int n = 0; n < 1000000 && !readers_done; ++n) {
      const Made& made = bricks[pick(rng)];
      cache.insert(made.key, kB, texture.channels, made.planar);  // may be refused
      ++inserted;
      if (n % 50 == 0) cache.begin_frame();
      if (cache.stats().resident_bytes > budget) failed = true;
    }
  };
  std::thread w(writer);
  std::thread r1(reader, 1u);
  std::thread r2(reader, 2u);
  r1.join();
  r2.join();
  readers_done = true;
  w.join();

  EXPECT_FALSE(failed);
  EXPECT_GT(inserted, 0);
  const BrickCacheStats s = cache.stats();
  EXPECT_LE(s.resident_bytes, budget);
  EXPECT_LE(s.peak_resident_bytes, budget);
  EXPECT_GT(s.evictions, 0u);
  EXPECT_EQ(s.lookups, s.hits + s.misses);
  EXPECT_GT(s.hits, 0u);
  EXPECT_TRUE(cache.contains(texture.key(coarsest, {0, 0, 0})));
}

}  // namespace
}  // namespace soltex
