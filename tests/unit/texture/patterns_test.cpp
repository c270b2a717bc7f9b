// Each lecture texture at hand-computed points, through the public evaluator.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "pattern_fields.h"
#include "soltex/common/texture_evaluator.h"

namespace soltex {
namespace {

TextureSpec spec_of(Pattern pattern) {
  TextureSpec spec;
  spec.pattern = std::move(pattern);
  return spec;
}

float field_at(const TextureEvaluator& t, double x, double y = 0.0, double z = 0.0) {
  return t.sample(glm::dvec3(x, y, z)).field;
}

TEST(Stripes, FlooredModuloIncludingNegatives) {
  const TextureEvaluator t(spec_of(StripesParams{1.0, 0.0, Axis::x}));
  EXPECT_EQ(field_at(t, 0.5), 0.0f);
  EXPECT_EQ(field_at(t, 1.5), 1.0f);
  EXPECT_EQ(field_at(t, -0.5), 1.0f);  // floor(-0.5) = -1: odd
  EXPECT_EQ(field_at(t, -1.0), 1.0f);  // exact negative integer
  EXPECT_EQ(field_at(t, -2.0), 0.0f);
  EXPECT_EQ(field_at(t, -1e-300), 1.0f);
  EXPECT_EQ(field_at(t, 0.0), 0.0f);
}

TEST(Stripes, OffsetWidthAxisAndColours) {
  const TextureEvaluator t(spec_of(StripesParams{2.0, 0.5, Axis::z}));
  EXPECT_EQ(field_at(t, 9.0, 9.0, 0.9), 0.0f);   // floor(0.5 + 0.45) = 0
  EXPECT_EQ(field_at(t, 9.0, 9.0, 1.0), 1.0f);   // floor(0.5 + 0.5) = 1
  EXPECT_EQ(field_at(t, 0.0, 0.0, -1.2), 1.0f);  // floor(0.5 - 0.6) = -1
  const ColourRamp ramp = t.spec().ramp;
  EXPECT_EQ(t.sample({0, 0, 0}).colour, ramp.keys.front().colour);  // yellow
  EXPECT_EQ(t.sample({0, 0, 1}).colour, ramp.keys.back().colour);   // red
}

TEST(Checker, TwoDimensionalParityOfNegativeSums) {
  const TextureEvaluator t(spec_of(CheckerParams{glm::dvec3(1.0), 0.0, false}));
  EXPECT_EQ(field_at(t, 0.5, 0.5), 0.0f);
  EXPECT_EQ(field_at(t, -0.5, 0.5), 1.0f);      // -1 + 0
  EXPECT_EQ(field_at(t, -0.5, -0.5), 0.0f);     // -1 + -1 = -2: even
  EXPECT_EQ(field_at(t, -1.5, 0.5), 0.0f);      // -2 + 0
  EXPECT_EQ(field_at(t, 0.5, 0.5, 7.5), 0.0f);  // z ignored in 2D
}

TEST(Checker, ThreeDimensionalParity) {
  const TextureEvaluator t(spec_of(CheckerParams{glm::dvec3(0.5, 1.0, 2.0), 0.0, true}));
  EXPECT_EQ(field_at(t, 0.25, 0.5, 1.0), 0.0f);
  EXPECT_EQ(field_at(t, 0.75, 0.5, 1.0), 1.0f);     // 1 + 0 + 0
  EXPECT_EQ(field_at(t, -0.25, -0.5, -1.0), 1.0f);  // -1 - 1 - 1 = -3: odd
  EXPECT_EQ(field_at(t, -0.25, -0.5, 1.0), 0.0f);   // -1 - 1 + 0 = -2
}

TEST(ColourCube, TriangleWavePerAxis) {
  const TextureEvaluator t(spec_of(ColourCubeParams{1.0}));
  EXPECT_EQ(t.sample({0.25, 0.5, 0.75}).colour, glm::vec3(0.5f, 1.0f, 0.5f));
  EXPECT_EQ(t.sample({0.0, 1.0, -2.0}).colour, glm::vec3(0.0f));
  EXPECT_EQ(t.sample({-0.25, 2.5, -7.875}).colour, glm::vec3(0.5f, 1.0f, 0.25f));
}

TEST(ColourCube, SymmetricAboutEveryInteger) {
  const TextureEvaluator t(spec_of(ColourCubeParams{2.0}));
  for (double x = 0.0; x < 4.0; x += 0.015625) {  // dyadic: exact fractions
    for (double c : {0.0, 2.0, -6.0}) {
      EXPECT_EQ(t.sample({c + x, 0, 0}).colour.r, t.sample({c - x, 0, 0}).colour.r) << x;
    }
  }
}

TEST(Rings, RadiusAboutZAxis) {
  const TextureEvaluator t(spec_of(RingsParams{0.1, 0.0, 1.0}));
  EXPECT_EQ(field_at(t, 0.05, 0.0), 0.0f);
  EXPECT_EQ(field_at(t, 0.15, 0.0), 1.0f);
  EXPECT_EQ(field_at(t, 0.0, -0.25), 0.0f);         // r / M = 2.5
  EXPECT_EQ(field_at(t, -0.09, 0.12, 55.0), 1.0f);  // r = 0.15, any z
}

TEST(Rings, BaseAndAmplitude) {
  const TextureEvaluator t(spec_of(RingsParams{1.0, 0.25, 0.5}));  // D + A * rings
  EXPECT_EQ(field_at(t, 0.5, 0.0), 0.25f);
  EXPECT_EQ(field_at(t, 1.5, 0.0), 0.75f);
}

TEST(Wood, DarkGrainIsTheThinColour) {
  const WoodParams params;
  const TextureEvaluator t(spec_of(params));
  int dark = 0, total = 0;
  for (double x = -1.0; x < 1.0; x += 0.01) {
    for (double y = -1.0; y < 1.0; y += 0.05) {
      const float f = field_at(t, x, y, 0.3);
      ASSERT_TRUE(f == 0.0f || f == 1.0f);
      dark += f == 1.0f;
      ++total;
    }
  }
  EXPECT_NEAR(static_cast<double>(dark) / total, params.grain_fraction, 0.05);
}

TEST(Wood, JitterIsRepeatable) {
  const TextureEvaluator a(spec_of(WoodParams{}));
  const TextureEvaluator b(spec_of(WoodParams{}));
  for (double x = -2.0; x < 2.0; x += 0.0731) {
    EXPECT_EQ(field_at(a, x, 0.4 * x, 0.7), field_at(b, x, 0.4 * x, 0.7));
  }
}

TEST(Marble, WithoutTurbulenceIsThePlainRipple) {
  MarbleParams params;
  params.amplitude = 0.0;
  params.frequency = 3.0;
  const TextureEvaluator t(spec_of(params));
  for (double x = -2.0; x < 2.0; x += 0.01) {
    const double expected = 0.5 + 0.5 * std::sin(2.0 * std::numbers::pi * 3.0 * x);
    EXPECT_NEAR(field_at(t, x, 0.3, -0.2), expected, 1e-6) << x;
  }
}

TEST(Marble, ProductRippleIsTheSlidesFormula) {
  MarbleParams params;
  params.ripple = Ripple::product;
  params.frequency = 1.0;
  params.amplitude = 0.0;
  const TextureEvaluator t(spec_of(params));
  const double x = 0.3, y = -0.7, z = 1.1;
  EXPECT_NEAR(field_at(t, x, y, z), 0.5 + 0.5 * std::sin(2.0 * std::numbers::pi * x * y * z), 1e-6);
}

TEST(Marble, FarFromOriginKeepsItsPrecision) {
  // The ripple is reduced by its period before the 2 pi multiplication: a point 1e9 periods
  // away (an exact shift) has the same ripple phase.
  MarbleParams params;
  params.amplitude = 0.0;
  params.frequency = 1.0;
  const TextureEvaluator t(spec_of(params));
  EXPECT_EQ(field_at(t, 0.375), field_at(t, 0.375 + 1e9));
  EXPECT_NEAR(field_at(t, 0.375), 0.5 + 0.5 * std::sin(0.75 * std::numbers::pi), 1e-7);
}

TEST(AllPatterns, LargeAndNonFiniteInputsGiveDefinedValues) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const Pattern patterns[] = {StripesParams{}, CheckerParams{}, ColourCubeParams{}, RingsParams{},
                              WoodParams{},    NoiseParams{},   TurbulenceParams{}, MarbleParams{}};
  for (const Pattern& pattern : patterns) {
    const TextureEvaluator t(spec_of(pattern));
    for (double v : {8388608.0, 1e7, 2147483648.5, 1e12, -1e12, nan, inf, -inf}) {
      for (const glm::dvec3& p : {glm::dvec3(v, 0.25, 0.5), glm::dvec3(v, v, v)}) {
        const Texel texel = t.sample(p);
        EXPECT_TRUE(std::isfinite(texel.field)) << pattern_name(pattern) << " at " << v;
        EXPECT_GE(texel.field, 0.0f) << pattern_name(pattern);
        EXPECT_LE(texel.field, 1.0f) << pattern_name(pattern);
        for (int c = 0; c < 3; ++c) {
          EXPECT_TRUE(texel.colour[c] >= 0.0f && texel.colour[c] <= 1.0f) << pattern_name(pattern);
        }
      }
    }
  }
}

TEST(AllPatterns, NonFiniteStripesAndCheckersTakeParityZero) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(field_at(TextureEvaluator(spec_of(StripesParams{})), nan), 0.0f);
  EXPECT_EQ(field_at(TextureEvaluator(spec_of(CheckerParams{})), nan, 0.5), 0.0f);
  EXPECT_EQ(field_at(TextureEvaluator(spec_of(RingsParams{})), nan, 0.0), 0.0f);
}

}  // namespace
}  // namespace soltex

// TextureEvaluator::sample() reads checkers through a runtime-dispatched batch kernel whose
// branches are selects: on this CPU's best target it must give fields::checker()'s bits for
// every point and box, through each of filtered_parity()'s cases (point, filtered, mean,
// non-finite) and far from the origin.
TEST(Checker, BatchKernelMatchesTheScalarFieldBitForBit) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<glm::dvec3> points;
  std::vector<soltex::SampleFootprint> footprints;
  const double boxes[] = {0.0, 1e-10, 1e-3, 0.07, 0.4, 1.3, 5.0, 2e8, inf, nan, -1.0};
  const double offsets[] = {0.0, -0.3, 0.61, 1e6 + 0.17, -1e9 - 0.41, 3.999999};
  for (const double o : offsets) {
    for (const double b : boxes) {
      for (int k = 0; k < 7; ++k) {
        points.emplace_back(o + 0.13 * k, -o + 0.29 * k, 0.5 * o - 0.07 * k);
        footprints.push_back({b, glm::dvec3(b, 0.5 * b, 2.0 * b)});
      }
    }
  }
  points.emplace_back(inf, 0.0, 0.0);
  points.emplace_back(0.0, nan, 0.0);
  points.emplace_back(0.0, 0.0, -inf);
  for (int k = 0; k < 3; ++k) footprints.push_back(soltex::SampleFootprint::isotropic(0.1));
  for (const bool three_d : {false, true}) {
    soltex::TextureSpec spec;
    spec.pattern = soltex::CheckerParams{{0.4, 0.25, 0.7}, 0.5, three_d};
    const soltex::CheckerParams& c = std::get<soltex::CheckerParams>(spec.pattern);
    const soltex::TextureEvaluator evaluator(spec);
    std::vector<soltex::Texel> texels(points.size());
    evaluator.sample(points, footprints, texels);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const float expected = soltex::fields::checker(c, points[i], footprints[i].box);
      EXPECT_EQ(std::bit_cast<uint32_t>(texels[i].field), std::bit_cast<uint32_t>(expected))
          << "point " << i << ", three_d " << three_d;
    }
  }
}
