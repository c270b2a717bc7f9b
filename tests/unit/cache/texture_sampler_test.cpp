#include "soltex/common/texture_sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "../texture/dispatch_targets.h"
#include "nearest_levels.h"
#include "real_bricks.h"

namespace soltex {
namespace {

using testing::RealTexture;
using testing::spec_of;

constexpr double kQuantizationStep = 1.0 / 255.0;
// Float arithmetic of the trilinear kernel and the float conversions of the evaluator.
constexpr double kRounding = 1e-5;
constexpr std::size_t kBigBudget = std::size_t{256} << 20;

// An offset, non-unit box: positions are not exact binary fractions of it.
Volume test_volume(int finest_level_log2) {
  Volume volume;
  volume.min = glm::dvec3(-0.7, 0.3, 1.1);
  volume.max = volume.min + glm::dvec3(1.3);
  volume.finest_level_log2 = finest_level_log2;
  return volume;
}

struct NamedTexture {
  std::string name;
  TextureSpec spec;
};

// Every channel count the kernels dispatch on: 3 (SIMD), 4 (SIMD), 5 and 1 (scalar).
std::vector<NamedTexture> lattice_textures() {
  return {
      {"colour_cube_rgb", spec_of(ColourCubeParams{0.3})},
      {"marble_rgb_opacity", spec_of(MarbleParams{}, {true, true, false})},
      {"wood_all_channels", spec_of(WoodParams{}, {true, true, true})},
      {"turbulence_opacity_only", spec_of(TurbulenceParams{}, {false, true, false})},
      {"checker_3d_rgb", spec_of(CheckerParams{glm::dvec3(0.11, 0.13, 0.17), 0.25, true})},
  };
}

// The same bricks reported missing, in the same order.
bool same_misses(const MissedBricks& a, const MissedBricks& b) {
  return a.count == b.count && std::equal(a.keys.begin(), a.keys.begin() + a.count, b.keys.begin());
}

// Two lookups that answered alike: the level drawn, completeness and the bricks missed.
bool same_answer(const SampleResult& a, const MissedBricks& a_missed, const SampleResult& b,
                 const MissedBricks& b_missed) {
  return a.level == b.level && a.complete == b.complete && same_misses(a_missed, b_missed);
}

// At a lattice point the cache returns the stored sample: the direct band-limited value
// quantized, so within half a quantization step (the lookup's own fraction is a few ulps
// of a cell, its weight on the neighbouring sample negligible).
TEST(TextureSampler, LatticePointsMatchDirectEvaluation) {
  for (const NamedTexture& t : lattice_textures()) {
    SCOPED_TRACE(t.name);
    const RealTexture texture(t.spec, test_volume(5), 8);
    BrickCache cache(kBigBudget);
    texture.insert_all_levels(cache);
    TextureSampler sampler(cache, texture.id, texture.layout, texture.channels);
    for (int level = 0; level <= texture.layout.coarsest_level(); ++level) {
      const int n = texture.layout.bricks_per_axis(level);
      for (int bz = 0; bz < n; ++bz) {
        for (int by = 0; by < n; ++by) {
          for (int bx = 0; bx < n; ++bx) {
            const Grid grid = texture.layout.sample_grid(level, {bx, by, bz});
            // Every other sample keeps the test quick and still covers faces and corners.
            for (int k = 0; k < grid.count.z; k += 2) {
              for (int j = 0; j < grid.count.y; j += 2) {
                for (int i = 0; i < grid.count.x; i += 2) {
                  const glm::dvec3 p = grid.point(i, j, k);
                  const std::vector<float> direct = texture.direct(p, level);
                  for (SampleFilter filter : {SampleFilter::trilinear, SampleFilter::nearest}) {
                    const SampleResult cached = sampler.sample(p, level, filter);
                    ASSERT_EQ(cached.level, level);
                    ASSERT_TRUE(cached.complete);
                    for (int c = 0; c < texture.channels; ++c) {
                      ASSERT_NEAR(cached.values[static_cast<std::size_t>(c)],
                                  direct[static_cast<std::size_t>(c)],
                                  0.5 * kQuantizationStep + kRounding)
                          << "level " << level << " channel " << c << " filter "
                          << sample_filter_name(filter) << " lattice (" << grid.first.x + i << ", "
                          << grid.first.y + j << ", " << grid.first.z + k << ")";
                    }
                  }
                }
              }
            }
          }
        }
      }
    }
  }
}

// The colour cube's channels are triangle waves of one coordinate each:
// r = triangle(x / P), slope +-2/P, with a kink (slope change 4/P) at every half period.
// Trilinear interpolation of a function of x alone is linear interpolation along x between
// the cell's corner values (the y and z weights sum to 1). Where the cell holds no kink it is
// exact; with a kink at distance a from one corner and b = h - a from the other, the chord
// misses the function by at most (4/P) * a * b / h <= (4/P) * h / 4 = h / P (a cell shorter
// than half a period holds at most one kink). The corner values carry at most half a
// quantization step of error, which a convex combination keeps. So
//     |cached - f(p)| <= h_l / P + 0.5 / 255 + rounding.
// (The generic bound for a Lipschitz constant L, L * h * sqrt(3), is looser.)
TEST(TextureSampler, TrilinearErrorWithinLipschitzBound) {
  constexpr double kPeriod = 0.5;
  const RealTexture texture(spec_of(ColourCubeParams{kPeriod}), test_volume(5), 8);
  BrickCache cache(kBigBudget);
  texture.insert_all_levels(cache);
  TextureSampler sampler(cache, texture.id, texture.layout, texture.channels);
  const Volume& v = texture.layout.volume();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int level = 0; level <= texture.layout.coarsest_level(); ++level) {
    const double h = texture.layout.filter_width(level);
    ASSERT_LT(h, kPeriod / 2) << "the one-kink-per-cell argument needs h < P / 2";
    const double bound = h / kPeriod + 0.5 * kQuantizationStep + kRounding;
    double worst = 0.0;
    for (int n = 0; n < 20000; ++n) {
      const glm::dvec3 p = v.min + (v.max - v.min) * glm::dvec3(unit(rng), unit(rng), unit(rng));
      const SampleResult cached = sampler.sample(p, level, SampleFilter::trilinear);
      const std::vector<float> direct = texture.direct(p, level);
      for (int c = 0; c < 3; ++c) {
        const double error = std::fabs(cached.values[static_cast<std::size_t>(c)] -
                                       direct[static_cast<std::size_t>(c)]);
        worst = std::max(worst, error);
        ASSERT_LE(error, bound) << "level " << level << " channel " << c;
      }
    }
    // The bound is not vacuous: the worst error seen is a good part of it.
    EXPECT_GT(worst, 0.25 * bound) << "level " << level;
  }
}

// Bricks share their faces bit for bit, so lookups just either side of a face, which read
// two different bricks, agree up to float rounding.
TEST(TextureSampler, NoSeamsAcrossBrickFaces) {
  const RealTexture texture(spec_of(MarbleParams{}), test_volume(6), 8);
  BrickCache cache(kBigBudget);
  texture.insert_all_levels(cache);
  TextureSampler sampler(cache, texture.id, texture.layout, texture.channels);
  const Volume& v = texture.layout.volume();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  constexpr double kEpsilon = 1e-7;  // cells
  for (int level = 0; level <= texture.layout.coarsest_level(); ++level) {
    const glm::dvec3 h = texture.layout.spacing(level);
    const int bricks = texture.layout.bricks_per_axis(level);
    int faces_crossed = 0;
    for (int axis = 0; axis < 3; ++axis) {
      for (int face = 1; face < bricks; ++face) {
        const double u_face = face * texture.layout.brick_size();
        for (int n = 0; n < 50; ++n) {
          glm::dvec3 p = v.min + (v.max - v.min) * glm::dvec3(unit(rng), unit(rng), unit(rng));
          glm::dvec3 q = p;
          p[axis] = v.min[axis] + (u_face - kEpsilon) * h[axis];
          q[axis] = v.min[axis] + (u_face + kEpsilon) * h[axis];
          const BrickKey below = sampler.brick_key(p, level);
          const BrickKey above = sampler.brick_key(q, level);
          ASSERT_EQ(below.brick[axis] + 1, above.brick[axis]);
          ++faces_crossed;
          const SampleResult a = sampler.sample(p, level, SampleFilter::trilinear);
          const SampleResult b = sampler.sample(q, level, SampleFilter::trilinear);
          for (int c = 0; c < texture.channels; ++c) {
            ASSERT_NEAR(a.values[static_cast<std::size_t>(c)],
                        b.values[static_cast<std::size_t>(c)], kRounding)
                << "level " << level << " axis " << axis << " face " << face;
          }
        }
      }
    }
    if (level < texture.layout.coarsest_level()) {
      EXPECT_GT(faces_crossed, 0);
    }
  }
}

TEST(TextureSampler, QuadrilinearBlendsTwoLevelsByTheFraction) {
  const RealTexture texture(spec_of(MarbleParams{}), test_volume(5), 8);
  BrickCache cache(kBigBudget);
  texture.insert_all_levels(cache);
  TextureSampler sampler(cache, texture.id, texture.layout, texture.channels);
  const glm::dvec3 p = texture.layout.volume().min + glm::dvec3(0.41, 0.77, 0.29);
  const SampleResult fine = sampler.sample(p, 1, SampleFilter::trilinear);
  const SampleResult coarse = sampler.sample(p, 2, SampleFilter::trilinear);
  const SampleResult blend = sampler.sample(p, 1.25, SampleFilter::quadrilinear);
  EXPECT_EQ(blend.level, 1);
  EXPECT_TRUE(blend.complete);
  for (std::size_t c = 0; c < 3; ++c) {
    EXPECT_NEAR(blend.values[c], 0.75 * fine.values[c] + 0.25 * coarse.values[c], 1e-6);
  }
  // An integer level of detail is plain trilinear.
  const SampleResult whole = sampler.sample(p, 1.0, SampleFilter::quadrilinear);
  for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(whole.values[c], fine.values[c]);
  // Trilinear and nearest pick the nearest level.
  EXPECT_EQ(sampler.sample(p, 1.49, SampleFilter::trilinear).level, 1);
  EXPECT_EQ(sampler.sample(p, 1.5, SampleFilter::nearest).level, 2);
}

TEST(TextureSampler, MissFallsBackToNearestResidentCoarserLevel) {
  const RealTexture texture(spec_of(MarbleParams{}), test_volume(5), 8);
  const int coarsest = texture.layout.coarsest_level();
  ASSERT_EQ(coarsest, 2);
  BrickCache cache(kBigBudget);
  texture.insert_level(cache, coarsest);
  TextureSampler sampler(cache, texture.id, texture.layout, texture.channels);
  const glm::dvec3 p = texture.layout.volume().min + glm::dvec3(0.9, 0.2, 0.6);

  MissedBricks missed;
  const SampleResult fallback = sampler.sample(p, 0, SampleFilter::trilinear, &missed);
  const SampleResult direct_coarsest = sampler.sample(p, coarsest, SampleFilter::trilinear);
  EXPECT_EQ(fallback.level, coarsest);
  EXPECT_FALSE(fallback.complete);
  EXPECT_EQ(fallback.values, direct_coarsest.values);
  ASSERT_EQ(missed.count, 1);
  EXPECT_EQ(missed.keys[0], sampler.brick_key(p, 0));

  // Level 1 arrives for this brick: the nearest resident coarser level is now level 1.
  const BrickKey level1 = sampler.brick_key(p, 1);
  ASSERT_TRUE(texture.insert(cache, 1, level1.brick));
  const SampleResult nearer = sampler.sample(p, 0, SampleFilter::trilinear, &missed);
  EXPECT_EQ(nearer.level, 1);
  EXPECT_EQ(nearer.values, sampler.sample(p, 1, SampleFilter::trilinear).values);
  ASSERT_EQ(missed.count, 1);
  EXPECT_EQ(missed.keys[0], sampler.brick_key(p, 0));

  // Quadrilinear between levels 0 and 1 misses only level 0.
  const SampleResult blend = sampler.sample(p, 0.5, SampleFilter::quadrilinear, &missed);
  EXPECT_EQ(blend.level, 1);
  ASSERT_EQ(missed.count, 1);
  EXPECT_EQ(missed.keys[0], sampler.brick_key(p, 0));
}

TEST(TextureSampler, NothingResidentReportsTheWantedAndTheCoarsestBricks) {
  const RealTexture texture(spec_of(MarbleParams{}), test_volume(5), 8);
  BrickCache cache(kBigBudget);
  TextureSampler sampler(cache, texture.id, texture.layout, texture.channels);
  const glm::dvec3 p = texture.layout.volume().min + glm::dvec3(0.9, 0.2, 0.6);
  MissedBricks missed;
  const SampleResult r = sampler.sample(p, 0.5, SampleFilter::quadrilinear, &missed);
  EXPECT_EQ(r.level, -1);
  EXPECT_FALSE(r.complete);
  for (float value : r.values) EXPECT_EQ(value, 0.0f);
  ASSERT_EQ(missed.count, 3);
  EXPECT_EQ(missed.keys[0], sampler.brick_key(p, 0));
  EXPECT_EQ(missed.keys[1], texture.key(2, {0, 0, 0}));  // the coarsest, once
  EXPECT_EQ(missed.keys[2], sampler.brick_key(p, 1));
  const BrickCacheStats before = cache.stats();
  sampler.flush_statistics();
  const BrickCacheStats after = cache.stats();
  EXPECT_GT(after.misses, before.misses);
  EXPECT_EQ(after.hits, 0u);
}

// A cache that never held a brick skips the walk over the coarser levels (a client's first
// frame): it must answer exactly as a cache whose bricks are all of another texture, which
// walks.
TEST(TextureSampler, ANeverFilledCacheAnswersAsTheWalkDoes) {
  const RealTexture texture(spec_of(MarbleParams{}), test_volume(5), 8);
  const RealTexture other(spec_of(WoodParams{}), test_volume(5), 8);
  BrickCache never_filled(kBigBudget);
  BrickCache filled_elsewhere(kBigBudget);
  ASSERT_TRUE(other.insert(filled_elsewhere, other.layout.coarsest_level(), {0, 0, 0}));
  ASSERT_GT(filled_elsewhere.stats().insertions, 0u);
  TextureSampler skipping(never_filled, texture.id, texture.layout, texture.channels);
  TextureSampler walking(filled_elsewhere, texture.id, texture.layout, texture.channels);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> coordinate(-1.0, 2.5);  // inside and outside
  std::uniform_real_distribution<double> lod(-0.5, 3.5);
  for (int n = 0; n < 3000; ++n) {
    const glm::dvec3 p(coordinate(rng), coordinate(rng), coordinate(rng));
    const double l = lod(rng);
    const auto filter = static_cast<SampleFilter>(n % 3);
    MissedBricks skipped, walked;
    const SampleResult a = skipping.sample(p, l, filter, &skipped);
    const SampleResult b = walking.sample(p, l, filter, &walked);
    ASSERT_TRUE(same_answer(a, skipped, b, walked)) << n;
    ASSERT_EQ(a.values, b.values) << n;
  }
  skipping.flush_statistics();
  walking.flush_statistics();
  EXPECT_EQ(never_filled.stats().misses, filled_elsewhere.stats().misses);
}

// find_misses() answers as sample() does, level, completeness and missed keys, without reading
// a sample: with nothing resident, with a scattered part of the bricks and with all of them;
// for points inside and far outside, NaN and infinite coordinates and levels. Points in one
// brick at their level miss the same bricks (the shader looks a run up once per brick).
TEST(TextureSampler, FindMissesAnswersAsSampleDoes) {
  const RealTexture texture(spec_of(MarbleParams{}), test_volume(6), 8);
  const int coarsest = texture.layout.coarsest_level();
  BrickCache empty(kBigBudget);
  BrickCache partial(kBigBudget);
  BrickCache full(kBigBudget);
  texture.insert_all_levels(full);
  // Every third brick of each level but the coarsest: walks stop at several depths.
  for (int level = 0; level < coarsest; ++level) {
    const int per_axis = 1 << (coarsest - level);
    int n = 0;
    for (int z = 0; z < per_axis; ++z) {
      for (int y = 0; y < per_axis; ++y) {
        for (int x = 0; x < per_axis; ++x) {
          if (n++ % 3 == 0) {
            ASSERT_TRUE(texture.insert(partial, level, {x, y, z}));
          }
        }
      }
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double odd[] = {nan, inf, -inf, -1e300, 1e300, -0.0};
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> coordinate(-1.0, 2.5);
  std::uniform_real_distribution<double> lod(-0.5, coarsest + 0.5);
  for (BrickCache* cache : {&empty, &partial, &full}) {
    TextureSampler sampling(*cache, texture.id, texture.layout, texture.channels);
    TextureSampler finding(*cache, texture.id, texture.layout, texture.channels);
    for (int n = 0; n < 4000; ++n) {
      glm::dvec3 p(coordinate(rng), coordinate(rng), coordinate(rng));
      double l = lod(rng);
      if (n % 50 == 0) p[n % 3] = odd[(n / 50) % std::size(odd)];
      if (n % 70 == 0) l = odd[(n / 70) % std::size(odd)];
      const auto filter = static_cast<SampleFilter>(n % 3);
      MissedBricks sampled, found;
      const SampleResult a = sampling.sample(p, l, filter, &sampled);
      const SampleResult b = finding.find_misses(p, l, filter, &found);
      ASSERT_TRUE(same_answer(a, sampled, b, found)) << n;
      if (filter == SampleFilter::quadrilinear || !(l >= 0.0)) continue;
      // A second point in the same brick at the level: the same answer.
      const int level = static_cast<int>(std::min<double>(l, coarsest) + 0.5);
      const glm::dvec3 q = p + glm::dvec3(1e-3, -1e-3, 2e-3);
      if (finding.brick_of(q, level) != finding.brick_of(p, level)) continue;
      MissedBricks again;
      const SampleResult c = finding.find_misses(q, l, filter, &again);
      ASSERT_TRUE(same_answer(c, again, b, found)) << n;
    }
  }
}

// The shading pass's two-step path (locate and prefetch, read later) gives what sample() gives,
// bit for bit, for nearest and trilinear; a brick not resident is left to sample_after_miss().
TEST(TextureSampler, LocateThenReadEqualsSample) {
  const RealTexture texture(spec_of(MarbleParams{}), test_volume(5), 8);
  BrickCache cache(kBigBudget);
  texture.insert_all_levels(cache);
  TextureSampler sampler(cache, texture.id, texture.layout, texture.channels);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coordinate(-1.0, 2.5);
  std::uniform_int_distribution<int> level_of(0, texture.layout.coarsest_level());
  for (int n = 0; n < 2000; ++n) {
    const glm::dvec3 p(coordinate(rng), coordinate(rng), coordinate(rng));
    const int level = level_of(rng);
    glm::vec3 frac(0.0f);
    const uint8_t* cell = sampler.locate_rgb(p, level, frac);
    ASSERT_NE(cell, nullptr);
    alignas(16) float rgb[4];
    sampler.nearest_rgb(cell, frac, rgb);
    const SampleResult nearest = sampler.sample(p, level, SampleFilter::nearest);
    for (int c = 0; c < 3; ++c) ASSERT_EQ(rgb[c], nearest.values[static_cast<std::size_t>(c)]) << n;
    sampler.trilinear_rgb(cell, frac, rgb);
    const SampleResult trilinear = sampler.sample(p, level, SampleFilter::trilinear);
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(rgb[c], trilinear.values[static_cast<std::size_t>(c)]) << n;
    }
  }
  BrickCache empty(kBigBudget);
  TextureSampler missing(empty, texture.id, texture.layout, texture.channels);
  glm::vec3 frac(0.0f);
  const glm::dvec3 p = texture.layout.volume().min + glm::dvec3(0.4);
  EXPECT_EQ(missing.locate_rgb(p, 0, frac), nullptr);
  MissedBricks missed;
  const SampleResult after = missing.sample_after_miss(p, 0, SampleFilter::nearest, &missed);
  EXPECT_EQ(after.level, -1);
  ASSERT_EQ(missed.count, 2);
  EXPECT_EQ(missed.keys[0], missing.brick_key(p, 0));
}

TEST(TextureSampler, LevelOfDetailFromFootprint) {
  const BrickLayout layout(test_volume(6), 8);  // levels 0..3
  const double h0 = layout.filter_width(0);
  const double coarsest = layout.coarsest_level();
  ASSERT_EQ(coarsest, 3.0);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, h0), 0.0);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, 2 * h0), 1.0);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, 4 * h0), 2.0);
  EXPECT_NEAR(level_of_detail(layout, 3 * h0), std::log2(3.0), 1e-12);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, 0.5 * h0), 0.0);  // finer than level 0
  EXPECT_DOUBLE_EQ(level_of_detail(layout, 1e6 * h0), coarsest);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, std::numeric_limits<double>::max()), coarsest);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, std::numeric_limits<double>::infinity()), coarsest);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, std::numeric_limits<double>::quiet_NaN()), coarsest);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, -0.0), 0.0);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, -1.0), 0.0);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, -std::numeric_limits<double>::infinity()), 0.0);
  EXPECT_DOUBLE_EQ(level_of_detail(layout, std::numeric_limits<double>::denorm_min()), 0.0);
}

// Footprints around every place a table of `layout` and `bias` may step: every power-of-two
// neighbourhood of the thresholds, where the formula steps, random bit patterns, and the
// special values.
std::vector<float> footprints_to_check(const BrickLayout& layout, double bias,
                                       std::mt19937& random) {
  std::vector<float> footprints = {0.0f,
                                   -0.0f,
                                   -1.0f,
                                   std::numeric_limits<float>::infinity(),
                                   -std::numeric_limits<float>::infinity(),
                                   std::numeric_limits<float>::quiet_NaN(),
                                   -std::numeric_limits<float>::quiet_NaN(),
                                   std::numeric_limits<float>::denorm_min(),
                                   std::numeric_limits<float>::max()};
  const auto around = [&](float centre) {
    const uint32_t bits = std::bit_cast<uint32_t>(centre);
    for (uint32_t d = 0; d < 64; ++d) footprints.push_back(std::bit_cast<float>(bits - 32 + d));
  };
  const auto h0 = static_cast<float>(layout.filter_width(0));
  for (int e = -40; e <= 40; ++e) {
    around(std::ldexp(h0, e / 2) * (e % 2 != 0 ? std::sqrt(2.0f) : 1.0f));
  }
  // Around where the formula steps: h0 * 2^(k - 0.5 - bias).
  for (int k = -2; k <= layout.coarsest_level() + 2; ++k) {
    around(static_cast<float>(h0 * std::exp2(k - 0.5 - bias)));
  }
  for (int i = 0; i < 20000; ++i) {
    footprints.push_back(std::bit_cast<float>(static_cast<uint32_t>(random())));
  }
  return footprints;
}

constexpr int kFinestLevels[] = {4, 6, 9, 12};
constexpr double kBiases[] = {0.0, -0.5, 0.5, -1.25, 0.3, 2.0, -8.0, 8.0};

// The table gives the formula's level for every float, for several biases and layouts.
TEST(NearestLevelTable, EqualsTheFormulaForEveryFootprint) {
  std::mt19937 random(7);
  for (const int finest : kFinestLevels) {
    const BrickLayout layout(test_volume(finest), 8);
    for (const double bias : kBiases) {
      const NearestLevelTable table(layout, bias);
      for (const float footprint : footprints_to_check(layout, bias, random)) {
        ASSERT_EQ(table.level(footprint),
                  NearestLevelTable::level_by_formula(layout, bias, footprint))
            << "footprint " << footprint << " bias " << bias << " finest " << finest;
      }
    }
  }
}

// levels() gives level()'s value for each footprint on every Highway target this CPU runs,
// in batches of every size from 0 to past two of the widest vectors, whole vectors or not.
// Each batch is a vector of its own size, so that a read past its end is one past an
// allocation (which the sanitizer build reports), and nothing past a batch is written.
TEST(NearestLevelTable, LevelsInLanesEqualLevelOnEveryTarget) {
  const std::vector<int64_t> targets = test::targets_to_run(nearest_levels_compiled_targets());
  ASSERT_FALSE(targets.empty());
  constexpr std::size_t kLargestBatch = 2 * 16 + 1;  // 16: AVX-512's floats
  std::mt19937 random(11);
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    ASSERT_EQ(nearest_levels_dispatched_target(), target) << hwy::TargetName(target);
    for (const int finest : kFinestLevels) {
      const BrickLayout layout(test_volume(finest), 8);
      for (const double bias : kBiases) {
        const NearestLevelTable table(layout, bias);
        const std::vector<float> footprints = footprints_to_check(layout, bias, random);
        constexpr int32_t kUntouched = -12345;
        // Batch k holds k % (kLargestBatch + 1) footprints (fewer at the end).
        for (std::size_t at = 0, k = 0, batch = 0; at < footprints.size(); at += batch, ++k) {
          batch = std::min(footprints.size() - at, k % (kLargestBatch + 1));
          const std::vector<float> in(footprints.begin() + static_cast<std::ptrdiff_t>(at),
                                      footprints.begin() + static_cast<std::ptrdiff_t>(at + batch));
          std::vector<int32_t> out(batch + 1, kUntouched);
          table.levels(in, out.data());
          for (std::size_t i = 0; i < batch; ++i) {
            ASSERT_EQ(out[i], table.level(in[i]))
                << hwy::TargetName(target) << " footprint " << in[i] << " bias " << bias
                << " finest " << finest << " batch " << batch;
          }
          ASSERT_EQ(out[batch], kUntouched) << hwy::TargetName(target) << " batch " << batch;
        }
      }
    }
  }
}

TEST(TextureSampler, OddLevelsAndPointsGiveDefinedSamples) {
  const RealTexture texture(spec_of(ColourCubeParams{0.3}), test_volume(5), 8);
  BrickCache cache(kBigBudget);
  texture.insert_all_levels(cache);
  TextureSampler sampler(cache, texture.id, texture.layout, texture.channels);
  const Volume& v = texture.layout.volume();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const int coarsest = texture.layout.coarsest_level();
  const glm::dvec3 inside = v.min + glm::dvec3(0.3, 0.6, 0.9);

  EXPECT_EQ(sampler.sample(inside, nan, SampleFilter::trilinear).level, coarsest);
  EXPECT_EQ(sampler.sample(inside, inf, SampleFilter::quadrilinear).level, coarsest);
  EXPECT_EQ(sampler.sample(inside, -inf, SampleFilter::trilinear).level, 0);
  EXPECT_EQ(sampler.sample(inside, -3.0, SampleFilter::nearest).level, 0);
  EXPECT_EQ(sampler.sample(inside, 99.0, SampleFilter::trilinear).level, coarsest);

  // Points outside the volume clamp to its faces; NaN coordinates go to the min face.
  const auto same = [&](const glm::dvec3& a, const glm::dvec3& b) {
    for (SampleFilter filter :
         {SampleFilter::nearest, SampleFilter::trilinear, SampleFilter::quadrilinear}) {
      const SampleResult ra = sampler.sample(a, 0.5, filter);
      const SampleResult rb = sampler.sample(b, 0.5, filter);
      EXPECT_EQ(ra.values, rb.values) << sample_filter_name(filter);
      EXPECT_TRUE(ra.complete);
    }
  };
  same(glm::dvec3(nan, nan, nan), v.min);
  same(glm::dvec3(-inf, 1e300, -1e300), glm::dvec3(v.min.x, v.max.y, v.min.z));
  same(glm::dvec3(inf, -5.0, nan), glm::dvec3(v.max.x, v.min.y, v.min.z));
  same(glm::dvec3(1e30, 1e30, 1e30), v.max);
}

// The vector split the sampler uses equals the scalar definition, including the odd inputs.
TEST(SampleSplit, VectorEqualsScalar) {
  const glm::dvec3 origin(-0.7, 0.3, 1.1);
  const glm::dvec3 spacing(1.3 / 64, 1.3 / 64, 1.3 / 64);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<glm::dvec3> points = {origin,
                                    origin + 64.0 * spacing,
                                    origin - spacing,
                                    origin + 1e-300,
                                    glm::dvec3(nan, inf, -inf),
                                    glm::dvec3(1e300, -1e300, -0.0),
                                    origin + 17.0 * spacing};
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> wide(-2.0, 3.0);
  for (int n = 0; n < 5000; ++n) points.emplace_back(wide(rng), wide(rng), wide(rng));
  for (const glm::dvec3& p : points) {
    for (int level = 0; level <= 3; ++level) {
      const double scale = std::ldexp(1.0, -level);
      const double cells = 64 >> level;
      const CellSplit fast = split_cell(p, origin, spacing, scale, cells);
      const CellSplit slow = split_cell_scalar(p, origin, spacing, scale, cells);
      ASSERT_EQ(fast.cell, slow.cell);
      for (int a = 0; a < 3; ++a) {
        ASSERT_EQ(std::signbit(fast.frac[a]), std::signbit(slow.frac[a]));
        ASSERT_EQ(fast.frac[a], slow.frac[a]);
        ASSERT_GE(fast.frac[a], 0.0f);
        ASSERT_LE(fast.frac[a], 1.0f);
        ASSERT_GE(fast.cell[a], 0);
        ASSERT_LT(fast.cell[a], cells);
      }
    }
  }
}

TEST(TextureSampler, ChannelCountIsChecked) {
  const BrickLayout layout(test_volume(5), 8);
  BrickCache cache(kBigBudget);
  EXPECT_THROW(TextureSampler(cache, 1, layout, 0), std::invalid_argument);
  EXPECT_THROW(TextureSampler(cache, 1, layout, 6), std::invalid_argument);
  // A brick of another shape under the texture's key is not read.
  const std::vector<uint8_t> one_channel(9 * 9 * 9, 200);
  ASSERT_TRUE(cache.insert(BrickKey{1, 2, glm::ivec3(0)}, 8, 1, one_channel));
  TextureSampler sampler(cache, 1, layout, 3);
  const SampleResult r = sampler.sample(layout.volume().min, 2, SampleFilter::trilinear);
  EXPECT_EQ(r.level, -1);
}

}  // namespace
}  // namespace soltex
