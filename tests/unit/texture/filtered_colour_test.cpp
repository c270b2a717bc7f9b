// A filtered sample's colour: the ramp averaged over the field's values within the sample's box
// (ColourRamp::average), checked against numerical averages of point samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "pattern_fields.h"
#include "soltex/common/texture_evaluator.h"

namespace soltex {
namespace {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// The ramp's mean over [t - spread, t + spread] by the midpoint rule.
glm::dvec3 numerical_average(const ColourRamp& ramp, float t, float spread) {
  constexpr int kSteps = 40000;
  glm::dvec3 sum(0.0);
  for (int i = 0; i < kSteps; ++i) {
    const double u = (i + 0.5) / kSteps;
    sum += glm::dvec3(ramp.at(static_cast<float>(t - spread + 2.0 * spread * u)));
  }
  return sum / static_cast<double>(kSteps);
}

// Keys at non-decreasing positions in [0, 1], two of them sometimes at one position (a jump).
ColourRamp random_ramp(std::mt19937_64& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_int_distribution<int> count(1, 6);
  std::vector<float> positions(static_cast<std::size_t>(count(rng)));
  for (float& p : positions) p = unit(rng);
  std::sort(positions.begin(), positions.end());
  if (positions.size() > 2 && unit(rng) < 0.3f) positions[1] = positions[2];
  ColourRamp ramp;
  for (float p : positions) ramp.keys.push_back({p, {unit(rng), unit(rng), unit(rng)}});
  return ramp;
}

TEST(ColourRampAverage, WithoutASpreadItIsThePointColour) {
  const ColourRamp ramp{{{0.2f, {0.1f, 0.2f, 0.3f}}, {0.7f, {0.9f, 0.5f, 0.0f}}}};
  for (float t : {-1.0f, 0.2f, 0.33f, 0.7f, 2.0f, kNan, kInf, -kInf}) {
    for (float spread : {0.0f, -0.5f, kNan}) {
      const glm::vec3 a = ramp.average(t, spread), b = ramp.at(t);
      EXPECT_EQ(a, b) << t << " " << spread;
    }
  }
}

TEST(ColourRampAverage, IsTheRampsMeanOverTheSpread) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> centre(-0.5f, 1.5f);
  std::uniform_real_distribution<float> log_spread(-3.0f, 0.0f);
  for (int trial = 0; trial < 300; ++trial) {
    const ColourRamp ramp = random_ramp(rng);
    const float t = centre(rng);
    const float spread = std::pow(10.0f, log_spread(rng));
    const glm::vec3 got = ramp.average(t, spread);
    const glm::dvec3 want = numerical_average(ramp, t, spread);
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(got[c], want[c], 2e-4) << "trial " << trial << " t " << t << " spread " << spread
                                         << " keys " << ramp.keys.size();
    }
  }
}

// The steps' changes summed in float could land an ulp outside the colours; past the last key
// the colour is that key's, exactly, as at() gives it.
TEST(ColourRampAverage, StaysInTheUnitRangeAndHitsTheLastKey) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int trial = 0; trial < 2000; ++trial) {
    ColourRamp ramp = random_ramp(rng);
    ramp.keys.back().colour = glm::vec3(trial % 2 == 0 ? 0.0f : 1.0f);
    const float t = unit(rng) * 1.5f - 0.25f, spread = 0.5f * unit(rng) + 1e-3f;
    const glm::vec3 c = ramp.average(t, spread);
    for (int i = 0; i < 3; ++i) {
      ASSERT_GE(c[i], 0.0f) << trial;
      ASSERT_LE(c[i], 1.0f) << trial;
    }
    const float past = ramp.keys.back().position + spread + 0.01f;
    ASSERT_EQ(ramp.average(past, spread), ramp.keys.back().colour) << trial;
  }
}

TEST(ColourRampAverage, AJumpIsTheShareOfTheBoxPastIt) {
  const glm::vec3 black(0.0f), white(1.0f);
  const ColourRamp jump{{{0.5f, black}, {0.5f, white}}};
  EXPECT_FLOAT_EQ(jump.average(0.5f, 0.1f).r, 0.5f);
  EXPECT_FLOAT_EQ(jump.average(0.55f, 0.1f).r, 0.75f);
  EXPECT_FLOAT_EQ(jump.average(0.35f, 0.1f).r, 0.0f);
  EXPECT_FLOAT_EQ(jump.average(0.65f, 0.1f).r, 1.0f);
}

TEST(ColourRampAverage, UnboundedFieldsTakeTheEndColours) {
  const ColourRamp ramp{{{0.2f, {0.1f, 0.2f, 0.3f}}, {0.7f, {0.9f, 0.5f, 0.0f}}}};
  EXPECT_EQ(ramp.average(kNan, 0.1f), ramp.keys.front().colour);
  EXPECT_EQ(ramp.average(-kInf, 0.1f), ramp.keys.front().colour);
  EXPECT_EQ(ramp.average(kInf, 0.1f), ramp.keys.back().colour);
}

TextureSpec spec_of(Pattern pattern, ColourRamp ramp = {}) {
  TextureSpec spec;
  spec.pattern = std::move(pattern);
  spec.ramp = std::move(ramp);
  return spec;
}

// Over random boxes of width w: the sample's colour against the mean of point samples' colours
// inside its box, the mean absolute error of the red channel.
double colour_error(const TextureEvaluator& texture, double width, int boxes = 16) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  double error = 0.0;
  for (int b = 0; b < boxes; ++b) {
    const glm::dvec3 centre(u(rng) * 4.0, u(rng) * 4.0, u(rng) * 4.0);
    constexpr int kPoints = 3000;
    double mean = 0.0;
    for (int i = 0; i < kPoints; ++i) {
      const glm::dvec3 p = centre + width * glm::dvec3(u(rng), u(rng), u(rng));
      mean += texture.sample(p).colour.r;
    }
    error += std::fabs(mean / kPoints - texture.sample(centre, width).colour.r);
  }
  return error / boxes;
}

// Marble's default ramp is far from linear: the ramp at the field's average (0.5 once the
// ripples are finer than the box) is near white, the mean of its colours a mid grey.
TEST(FilteredColour, MarbleFinerThanTheBoxTakesTheMeanOfItsColours) {
  MarbleParams marble;
  marble.frequency = 80.0;
  const TextureEvaluator texture(spec_of(marble));
  // The ramp of the field's average was off by 0.12 to 0.19 at these widths.
  for (double width : {0.0078, 0.0625, 0.25}) {
    EXPECT_LT(colour_error(texture, width), 0.04) << "width " << width;
  }
  const glm::vec3 coarse = texture.sample(glm::dvec3(0.1, 0.2, 0.3), 0.25).colour;
  EXPECT_LT(coarse.r, 0.8f);  // the ramp's colour at 0.5 is 0.92
}

// Turbulence's default ramp bends at 0.5. Where every octave is faded, the ramp is averaged
// over what they leave out (the ramp of the mean field was off by 0.035 at width 0.5); at
// middle widths the faded octaves' mean, not the ramp, decides the error.
TEST(FilteredColour, NoiseWithFadedOctavesTakesTheMeanOfItsColours) {
  const TextureEvaluator texture(spec_of(TurbulenceParams{{8.0, 0, 5, NoiseBasis::value, false}}));
  EXPECT_LT(colour_error(texture, 0.25), 0.04);
  EXPECT_LT(colour_error(texture, 0.5), 0.02);
}

// Two-valued fields blend the two values' colours: with black at both ends a stripe edge is
// black, whatever the ramp does between.
TEST(FilteredColour, TwoValuedFieldsBlendTheirTwoColours) {
  const ColourRamp hidden_middle{
      {{0.0f, glm::vec3(0.0f)}, {0.5f, glm::vec3(1.0f)}, {1.0f, glm::vec3(0.0f)}}};
  for (const Pattern& pattern : {Pattern{StripesParams{}}, Pattern{CheckerParams{}},
                                 Pattern{WoodParams{}}, Pattern{RingsParams{}}}) {
    const TextureEvaluator texture(spec_of(pattern, hidden_middle));
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int i = 0; i < 200; ++i) {
      const Texel texel = texture.sample(glm::dvec3(u(rng), u(rng), u(rng)), 0.3);
      ASSERT_EQ(texel.colour, glm::vec3(0.0f)) << pattern_name(pattern) << " field " << texel.field;
    }
  }
}

}  // namespace
}  // namespace soltex
