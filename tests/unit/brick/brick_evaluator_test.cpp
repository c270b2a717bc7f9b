#include "soltex/common/brick_evaluator.h"

#include <gtest/gtest.h>

#include <vector>

namespace soltex {
namespace {

std::vector<Pattern> all_patterns() {
  MarbleParams product;
  product.ripple = Ripple::product;
  return {StripesParams{0.13, 0.0, Axis::x},
          CheckerParams{glm::dvec3(0.07), 0.0, true},
          ColourCubeParams{0.3},
          RingsParams{0.05, 0.0, 1.0},
          WoodParams{},
          NoiseParams{9.0, NoiseBasis::gradient},
          TurbulenceParams{},
          MarbleParams{},
          product};
}

Volume test_volume() {
  Volume v;
  v.min = {-1.3, -0.2, 5.0};  // not centred, not a power of two: spacings are inexact
  v.max = {0.7, 2.1, 5.9};
  v.finest_level_log2 = 6;
  return v;
}

struct Brick {
  std::vector<float> samples;
  int channels;
  int n;  // samples per axis
  float at(int c, int x, int y, int z) const {
    return samples[static_cast<std::size_t>(c) * n * n * n +
                   (static_cast<std::size_t>(z) * n + y) * n + x];
  }
};

Brick make(const TextureEvaluator& t, const BrickLayout& layout, int level, glm::ivec3 b,
           const MipSettings& mip) {
  Brick brick{{}, t.spec().channels.sample_count(), layout.samples_per_axis()};
  brick.samples.resize(static_cast<std::size_t>(layout.samples_per_brick()) * brick.channels);
  evaluate_brick(t, layout, level, b, mip, brick.samples);
  return brick;
}

// Faces, edges and corners shared by neighbouring bricks are bit-identical, for every pattern,
// every level and every MIP mode.
TEST(EvaluateBrick, SharedFacesAreBitIdentical) {
  const BrickLayout layout(test_volume(), 8);
  const MipSettings modes[] = {
      {MipMode::point, 1}, {MipMode::band_limited, 1}, {MipMode::supersampled, 2}};
  for (const Pattern& pattern : all_patterns()) {
    TextureSpec spec;
    spec.pattern = pattern;
    spec.channels = {true, true, false};
    const TextureEvaluator t(spec);
    for (const MipSettings& mip : modes) {
      for (int level = 0; level < layout.level_count(); ++level) {
        const int bricks = layout.bricks_per_axis(level);
        const int last = layout.brick_size();
        for (int bz = 0; bz < bricks; ++bz) {
          for (int by = 0; by < bricks; ++by) {
            for (int bx = 0; bx < bricks; ++bx) {
              if (bricks > 2 && (bx + by + bz) % 3 != 0) continue;  // a spread of bricks
              const Brick here = make(t, layout, level, {bx, by, bz}, mip);
              for (int axis = 0; axis < 3; ++axis) {
                glm::ivec3 next(bx, by, bz);
                next[axis] += 1;
                if (next[axis] >= bricks) continue;
                const Brick there = make(t, layout, level, next, mip);
                for (int c = 0; c < here.channels; ++c) {
                  for (int u = 0; u < here.n; ++u) {
                    for (int v = 0; v < here.n; ++v) {
                      glm::ivec3 a(u, v, 0), b(u, v, 0);
                      // Put the face coordinate on `axis`.
                      a = axis == 0   ? glm::ivec3(last, u, v)
                          : axis == 1 ? glm::ivec3(u, last, v)
                                      : glm::ivec3(u, v, last);
                      b = axis == 0   ? glm::ivec3(0, u, v)
                          : axis == 1 ? glm::ivec3(u, 0, v)
                                      : glm::ivec3(u, v, 0);
                      ASSERT_EQ(here.at(c, a.x, a.y, a.z), there.at(c, b.x, b.y, b.z))
                          << pattern_name(pattern) << " " << mip_mode_name(mip.mode) << " level "
                          << level << " axis " << axis;
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

TEST(EvaluateBrick, PointModeSamplesTheFunctionAtLatticePoints) {
  const BrickLayout layout(test_volume(), 8);
  TextureSpec spec;
  spec.pattern = MarbleParams{};
  const TextureEvaluator t(spec);
  const Brick brick = make(t, layout, 1, {1, 0, 2}, {MipMode::point, 1});
  const Grid grid = layout.sample_grid(1, {1, 0, 2});
  EXPECT_EQ(brick.at(0, 3, 4, 5), t.sample(grid.point(3, 4, 5), 0.0).colour.r);
}

TEST(EvaluateBrick, BandLimitedUsesTheLevelSpacing) {
  const BrickLayout layout(test_volume(), 8);
  TextureSpec spec;
  spec.pattern = MarbleParams{};
  const TextureEvaluator t(spec);
  const int level = 2;
  const Brick brick = make(t, layout, level, {0, 1, 0}, {});
  const Grid grid = layout.sample_grid(level, {0, 1, 0});
  EXPECT_EQ(brick.at(1, 7, 0, 2),
            t.sample(grid.point(7, 0, 2), layout.filter_width(level)).colour.g);
}

TEST(EvaluateBrick, SupersamplingAveragesSubSamples) {
  const BrickLayout layout(test_volume(), 8);
  TextureSpec spec;
  spec.pattern = ColourCubeParams{0.3};
  const TextureEvaluator t(spec);
  const int level = 1, k = 2;
  const Brick brick = make(t, layout, level, {0, 0, 0}, {MipMode::supersampled, k});
  const Grid grid = layout.sample_grid(level, {0, 0, 0});
  const glm::dvec3 centre = grid.point(2, 3, 4);
  // Each sub-sample is filtered over the sub-sample spacing, as the MIP mode says.
  const double filter = layout.filter_width(level) / k;
  double expected = 0.0;
  for (int sz = 0; sz < k; ++sz)
    for (int sy = 0; sy < k; ++sy)
      for (int sx = 0; sx < k; ++sx) {
        const glm::dvec3 offset = (glm::dvec3(sx, sy, sz) + 0.5) / double(k) - 0.5;
        expected += t.sample(centre + offset * grid.step, filter).colour.r / (k * k * k);
      }
  EXPECT_NEAR(brick.at(0, 2, 3, 4), expected, 1e-6);
}

TEST(EvaluateBrick, RejectsBricksOutsideTheVolume) {
  const BrickLayout layout(test_volume(), 8);
  TextureSpec spec;
  spec.pattern = StripesParams{};
  const TextureEvaluator t(spec);
  std::vector<float> out(static_cast<std::size_t>(layout.samples_per_brick()) * 3);
  EXPECT_THROW(evaluate_brick(t, layout, 0, {8, 0, 0}, {}, out), std::invalid_argument);
  EXPECT_THROW(evaluate_brick(t, layout, layout.level_count(), {0, 0, 0}, {}, out),
               std::invalid_argument);
  EXPECT_THROW(evaluate_brick(t, layout, 0, {0, 0, 0}, {MipMode::supersampled, 9}, out),
               std::invalid_argument);
}

}  // namespace
}  // namespace soltex
