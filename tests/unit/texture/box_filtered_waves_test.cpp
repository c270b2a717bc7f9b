// The closed-form box filters of the hard-edged waves against numerical averages, their limits
// (a point, a box much wider than the period) and their precision far from the origin.
#include "box_filtered_waves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "soltex/common/texture_evaluator.h"

namespace soltex {
namespace {

// The midpoint-rule average of f over [u - w/2, u + w/2] with n samples.
double numerical_average(const std::function<double(double)>& f, double u, double w,
                         int n = 200000) {
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += f(u - 0.5 * w + (i + 0.5) * w / n);
  return sum / n;
}

TEST(BoxFilteredWaves, ParityMatchesNumericalAverage) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> position(-5.0, 5.0), width(0.01, 6.0);
  for (int i = 0; i < 40; ++i) {
    const double u = position(rng), w = width(rng);
    const double expected = numerical_average([](double x) { return floor_parity(x); }, u, w);
    EXPECT_NEAR(waves::filtered_parity(u, w), expected, 2e-4) << "u=" << u << " w=" << w;
  }
}

TEST(BoxFilteredWaves, PulseAndTriangleMatchNumericalAverage) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> position(-5.0, 5.0), width(0.01, 3.0), duty(0.05, 0.95);
  for (int i = 0; i < 40; ++i) {
    const double u = position(rng), w = width(rng), d = duty(rng);
    const double pulse =
        numerical_average([d](double x) { return fract(x) < d ? 1.0 : 0.0; }, u, w);
    EXPECT_NEAR(waves::filtered_pulse(u, d, w), pulse, 2e-4) << "u=" << u << " w=" << w;
    const double triangle =
        numerical_average([](double x) { return 1.0 - std::fabs(2.0 * fract(x) - 1.0); }, u, w);
    EXPECT_NEAR(waves::filtered_triangle(u, w), triangle, 2e-4) << "u=" << u << " w=" << w;
  }
}

TEST(BoxFilteredWaves, ZeroWidthIsThePointValue) {
  for (double u : {-2.5, -1.0, -1e-300, 0.0, 0.25, 1.0, 1.75, 3e9 + 0.5}) {
    EXPECT_EQ(waves::filtered_parity(u, 0.0), floor_parity(u)) << u;
    EXPECT_EQ(waves::filtered_pulse(u, 0.3, 0.0), fract(u) < 0.3 ? 1.0 : 0.0) << u;
    EXPECT_EQ(waves::filtered_triangle(u, 0.0), 1.0 - std::fabs(2.0 * fract(u) - 1.0)) << u;
  }
}

TEST(BoxFilteredWaves, WideBoxesGiveTheMean) {
  for (double w : {64.0, 1e3 + 0.37, 1e6, 1e9, std::numeric_limits<double>::infinity()}) {
    EXPECT_NEAR(waves::filtered_parity(0.3, w), 0.5, 1.0 / w + 1e-12) << w;
    EXPECT_NEAR(waves::filtered_pulse(0.3, 0.2, w), 0.2, 1.0 / w + 1e-12) << w;
    EXPECT_NEAR(waves::filtered_triangle(0.3, w), 0.5, 1.0 / w + 1e-12) << w;
  }
}

TEST(BoxFilteredWaves, FarFromTheOriginAsNearIt) {
  // Reduced by the period first: 2^40 + u filters as u does.
  const double far = std::ldexp(1.0, 40);
  for (double u : {0.125, 0.875, 1.0625, 1.5}) {  // exact at 2^40 too
    for (double w : {0.01, 0.3, 1.7}) {
      EXPECT_DOUBLE_EQ(waves::filtered_parity(far + u, w), waves::filtered_parity(u, w));
      EXPECT_DOUBLE_EQ(waves::filtered_pulse(far + u, 0.2, w), waves::filtered_pulse(u, 0.2, w));
    }
  }
}

TEST(BoxFilteredWaves, NonFiniteInputsAreDefined) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double u : {nan, inf, -inf}) {
    for (double w : {0.0, 0.5, inf, nan}) {
      EXPECT_EQ(waves::filtered_parity(u, w), 0.0);
      EXPECT_TRUE(std::isfinite(waves::filtered_pulse(u, 0.2, w)));
      EXPECT_TRUE(std::isfinite(waves::filtered_triangle(u, w)));
    }
  }
  EXPECT_TRUE(std::isfinite(waves::filtered_parity(0.5, nan)));
}

TextureSpec spec_of(Pattern pattern) {
  TextureSpec spec;
  spec.pattern = std::move(pattern);
  return spec;
}

TEST(FilteredPatterns, CheckerFinerThanTheBoxIsItsMean) {
  // A 3D checker of 1e-6 cells seen through a box of 1e-3: the flat average, everywhere.
  const TextureEvaluator t(spec_of(CheckerParams{glm::dvec3(1e-6), 0.0, true}));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> position(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    const glm::dvec3 p(position(rng), position(rng), position(rng));
    EXPECT_NEAR(t.sample(p, 1e-3).field, 0.5f, 1e-3f);
  }
}

TEST(FilteredPatterns, ABoxWithNoExtentAcrossAnEdgeKeepsItCrisp) {
  // A face at x = 0.5 on a checker boundary, looked at just inside: the box lies in the face's
  // plane, so the x edge is not blurred while y and z are averaged.
  const TextureEvaluator t(spec_of(CheckerParams{glm::dvec3(0.25), 0.0, true}));
  const SampleFootprint in_plane{0.01, {0.0, 0.01, 0.01}};
  const double inside = 0.5 - 1e-6;
  EXPECT_EQ(t.sample({inside, 0.1, 0.1}, in_plane).field, t.sample({inside, 0.1, 0.1}).field);
  EXPECT_NEAR(t.sample({inside, 0.25, 0.1}, in_plane).field, 0.5f, 1e-6f);  // on a y edge
  // Isotropic, the same point blends across x.
  EXPECT_NEAR(t.sample({0.5, 0.1, 0.1}, 0.01).field, 0.5f, 1e-6f);
}

TEST(FilteredPatterns, RingsAndWoodFadeToTheirMeans) {
  const TextureEvaluator rings(spec_of(RingsParams{1e-4, 0.2, 0.6}));
  EXPECT_NEAR(rings.sample({0.3, 0.4, 0.0}, 0.05).field, 0.2f + 0.3f, 2e-3f);
  WoodParams wood;
  wood.ring_spacing = 1e-4;
  const TextureEvaluator grain(spec_of(wood));
  EXPECT_NEAR(grain.sample({0.3, 0.4, 0.1}, 0.05).field, wood.grain_fraction, 2e-2f);
}

}  // namespace
}  // namespace soltex
