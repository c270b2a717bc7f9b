#include "soltex/common/texture_evaluator.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <vector>

#include "soltex/common/spec_error.h"

namespace soltex {
namespace {

std::vector<Pattern> all_patterns() {
  MarbleParams product;
  product.ripple = Ripple::product;
  MarbleParams gradient_marble;
  gradient_marble.turbulence.basis = NoiseBasis::gradient;
  return {StripesParams{0.3, 0.1, Axis::y},
          CheckerParams{glm::dvec3(0.2, 0.3, 0.4), 0.5, true},
          ColourCubeParams{0.7},
          RingsParams{},
          WoodParams{},
          NoiseParams{5.0, NoiseBasis::value},
          NoiseParams{5.0, NoiseBasis::gradient},
          TurbulenceParams{{3.0, 0, 7, NoiseBasis::value, false}},
          TurbulenceParams{{3.0, 1, 6, NoiseBasis::gradient, true}},
          MarbleParams{},
          product,
          gradient_marble};
}

TEST(TextureEvaluator, BatchEqualsSinglePointBitForBit) {
  const Grid grids[] = {
      {{-1.0, -0.5, 0.25}, {0.037, 0.05, 0.11}, {23, 5, 3}},
      {{1e6 + 0.3, -2e6, 7.0}, {0.001, 0.013, 0.2}, {40, 2, 2}},
      {{-3.0, -3.0, -3.0}, {0.25, 0.25, 0.25}, {25, 25, 1}},
      {{0.5, -0.25, 3.0}, {0.01, 0.02, 0.03}, {9, 4, 2}, {-1000, 7, 123456}},
  };
  for (const Pattern& pattern : all_patterns()) {
    TextureSpec spec;
    spec.pattern = pattern;
    spec.channels = {true, true, true};
    const TextureEvaluator t(spec);
    for (const Grid& grid : grids) {
      for (double width : {0.0, 0.01, 0.2}) {
        std::vector<float> out(grid.size() * 5);
        t.evaluate_grid(grid, width, out);
        const std::size_t n = grid.size();
        std::size_t i = 0;
        for (int z = 0; z < grid.count.z; ++z) {
          for (int y = 0; y < grid.count.y; ++y) {
            for (int x = 0; x < grid.count.x; ++x, ++i) {
              const Texel texel = t.sample(grid.point(x, y, z), width);
              ASSERT_EQ(out[i], texel.colour.r) << pattern_name(pattern) << " i=" << i;
              ASSERT_EQ(out[n + i], texel.colour.g) << pattern_name(pattern);
              ASSERT_EQ(out[2 * n + i], texel.colour.b) << pattern_name(pattern);
              ASSERT_EQ(out[3 * n + i], texel.field) << pattern_name(pattern);  // opacity 0..1
              ASSERT_EQ(out[4 * n + i], texel.field) << pattern_name(pattern);
            }
          }
        }
      }
    }
  }
}

// The many-point form plans octaves per point: widths that change, repeat after a change, or
// are 0, negative or NaN must each give the point's own result.
TEST(TextureEvaluator, ManyPointsEqualOnePointAtATimeBitForBit) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double widths[] = {0.01, 0.01, 0.0, 0.2, 0.01, nan, -1.0, 0.2, 0.2, 3e-5, 0.01};
  std::vector<glm::dvec3> points;
  std::vector<SampleFootprint> footprints;
  for (int i = 0; i < 64; ++i) {
    const double u = 0.173 * i - 4.0;
    points.emplace_back(u, 0.5 * u + 0.31, 1e4 - 0.07 * u);
    const double w = widths[static_cast<std::size_t>(i) % std::size(widths)];
    footprints.push_back({w, glm::dvec3(0.3 * (i % 5), 0.01 * (i % 3), w)});
  }
  for (const Pattern& pattern : all_patterns()) {
    TextureSpec spec;
    spec.pattern = pattern;
    const TextureEvaluator t(spec);
    std::vector<Texel> many(points.size());
    t.sample(points, footprints, many);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Texel one = t.sample(points[i], footprints[i]);
      ASSERT_EQ(many[i].field, one.field) << pattern_name(pattern) << " i=" << i;
      ASSERT_EQ(many[i].colour, one.colour) << pattern_name(pattern) << " i=" << i;
    }
  }
}

TEST(TextureEvaluator, ManyPointsNeedAFootprintEach) {
  const TextureEvaluator t(TextureSpec{});
  const std::vector<glm::dvec3> points(3);
  const std::vector<SampleFootprint> footprints(2);
  std::vector<Texel> out(3);
  EXPECT_THROW(t.sample(points, footprints, out), std::invalid_argument);
}

TEST(TextureEvaluator, ScalarChannelsMapTheFieldToTheirRange) {
  TextureSpec spec;
  spec.pattern = NoiseParams{};
  spec.channels = {false, false, true};
  spec.specular = {0.2f, 0.6f};
  const TextureEvaluator t(spec);
  const Grid grid{{0.1, 0.2, 0.3}, {0.05, 0.05, 0.05}, {8, 8, 8}};
  std::vector<float> out(grid.size());
  t.evaluate_grid(grid, 0.0, out);
  EXPECT_EQ(out[17], 0.2f + (0.6f - 0.2f) * t.sample(grid.point(1, 2, 0)).field);
}

TEST(TextureEvaluator, TooSmallOutputIsRejected) {
  TextureSpec spec;
  spec.pattern = StripesParams{};
  const TextureEvaluator t(spec);
  std::vector<float> out(10);
  const Grid grid{{0, 0, 0}, {1, 1, 1}, {4, 1, 1}};
  EXPECT_THROW(t.evaluate_grid(grid, 0.0, out), std::invalid_argument);
  const Grid empty{{0, 0, 0}, {1, 1, 1}, {0, 1, 1}};
  EXPECT_THROW(t.evaluate_grid(empty, 0.0, out), std::invalid_argument);
}

TEST(TextureEvaluator, InvalidSpecIsRejectedAtConstruction) {
  TextureSpec spec;
  spec.pattern = StripesParams{-1.0, 0.0, Axis::x};
  EXPECT_THROW(TextureEvaluator{spec}, SpecError);
}

TEST(TextureEvaluator, CoarseFilterWidthsEvaluateFewerOctaves) {
  TextureSpec spec;
  spec.pattern = MarbleParams{};
  const TextureEvaluator t(spec);
  EXPECT_EQ(t.evaluated_octaves(0.0), 6);
  EXPECT_LT(t.evaluated_octaves(1.0 / 64.0), 6);
  EXPECT_EQ(t.evaluated_octaves(10.0), 0);
  TextureSpec stripes;
  stripes.pattern = StripesParams{};
  EXPECT_EQ(TextureEvaluator(stripes).evaluated_octaves(0.0), 0);
}

}  // namespace
}  // namespace soltex
