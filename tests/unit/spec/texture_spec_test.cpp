#include "soltex/common/texture_spec.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

#include "soltex/common/spec_error.h"

namespace soltex {
namespace {

using ::testing::HasSubstr;

// Runs validated() and returns the SpecError it throws.
template <typename T>
SpecError error_of(T value) {
  try {
    (void)validated(std::move(value));
  } catch (const SpecError& e) {
    return e;
  }
  ADD_FAILURE() << "expected a SpecError";
  return SpecError("", "", "");
}

TextureSpec spec_of(Pattern pattern) {
  TextureSpec spec;
  spec.pattern = std::move(pattern);
  return spec;
}

TEST(Validated, DefaultsAreValidAndGetTheirRamp) {
  for (const Pattern& p :
       {Pattern{StripesParams{}}, Pattern{CheckerParams{}}, Pattern{ColourCubeParams{}},
        Pattern{RingsParams{}}, Pattern{WoodParams{}}, Pattern{NoiseParams{}},
        Pattern{TurbulenceParams{}}, Pattern{MarbleParams{}}}) {
    const TextureSpec spec = validated(spec_of(p));
    EXPECT_FALSE(spec.ramp.keys.empty()) << pattern_name(p);
  }
}

TEST(Validated, ErrorNamesFieldValueAndBound) {
  MarbleParams marble;
  marble.turbulence.octave_max = 40;
  const SpecError e = error_of(spec_of(marble));
  EXPECT_EQ(e.field(), "marble.turbulence.octave_max");
  EXPECT_EQ(e.value(), "40");
  EXPECT_THAT(e.what(), HasSubstr("marble.turbulence.octave_max = 40"));
  EXPECT_THAT(e.what(), HasSubstr("[0, 24]"));
}

TEST(Validated, NonFiniteParametersAreRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THAT(error_of(spec_of(StripesParams{nan, 0.0, Axis::x})).what(),
              HasSubstr("stripes.width = nan: must be finite"));
  EXPECT_EQ(error_of(spec_of(CheckerParams{glm::dvec3(1, inf, 1), 0.0, false})).field(),
            "checker.size.y");
  WoodParams wood;
  wood.twist = -inf;
  EXPECT_EQ(error_of(spec_of(wood)).field(), "wood.twist");
  MarbleParams marble;
  marble.amplitude = nan;
  EXPECT_EQ(error_of(spec_of(marble)).field(), "marble.amplitude");
}

TEST(Validated, BoundsOnSizesAndScales) {
  EXPECT_EQ(error_of(spec_of(StripesParams{0.0, 0.0, Axis::x})).field(), "stripes.width");
  EXPECT_EQ(error_of(spec_of(StripesParams{1e7, 0.0, Axis::x})).field(), "stripes.width");
  EXPECT_EQ(error_of(spec_of(RingsParams{-0.1, 0.0, 1.0})).field(), "rings.thickness");
  EXPECT_EQ(error_of(spec_of(ColourCubeParams{1e-9})).field(), "colour_cube.period");
  EXPECT_EQ(error_of(spec_of(NoiseParams{1e5, NoiseBasis::value})).field(), "noise.scale");
  WoodParams wood;
  wood.grain_fraction = 1.5;
  EXPECT_EQ(error_of(spec_of(wood)).field(), "wood.grain_fraction");
}

TEST(Validated, OctaveBounds) {
  TurbulenceParams t;
  t.fractal.octave_min = 5;
  t.fractal.octave_max = 3;
  EXPECT_EQ(error_of(spec_of(t)).field(), "turbulence.fractal.octave_min");
  t.fractal.octave_min = 0;
  t.fractal.octave_max = 20;
  const SpecError too_many = error_of(spec_of(t));
  EXPECT_EQ(too_many.field(), "turbulence.fractal.octave_max");
  EXPECT_THAT(too_many.what(), HasSubstr("at most 16 octaves"));
  t.fractal.octave_min = -1;
  t.fractal.octave_max = 3;
  EXPECT_EQ(error_of(spec_of(t)).field(), "turbulence.fractal.octave_min");
}

// signed_octaves changes gradient octaves only; asked of value noise it is refused, not
// ignored.
TEST(Validated, SignedOctavesNeedTheGradientBasis) {
  TurbulenceParams t;
  t.fractal.signed_octaves = true;
  t.fractal.basis = NoiseBasis::value;
  const SpecError e = error_of(spec_of(t));
  EXPECT_EQ(e.field(), "turbulence.fractal.signed_octaves");
  EXPECT_THAT(e.what(), HasSubstr("gradient basis only"));
  t.fractal.basis = NoiseBasis::gradient;
  EXPECT_NO_THROW(validated(spec_of(t)));
}

TEST(Validated, RampKeys) {
  TextureSpec spec = spec_of(NoiseParams{});
  spec.ramp.keys = {{0.6f, glm::vec3(0.0f)}, {0.2f, glm::vec3(1.0f)}};
  EXPECT_EQ(error_of(spec).field(), "ramp.keys[1].position");
  // As the floats they are: not 0.20000000298023224 and 0.6000000238418579.
  EXPECT_STREQ(error_of(spec).what(),
               "ramp.keys[1].position = 0.2: must be finite and in [0.6, 1]");
  spec.ramp.keys = {{0.0f, glm::vec3(0.0f, 2.0f, 0.0f)}};
  EXPECT_EQ(error_of(spec).field(), "ramp.keys[0].colour.g");
  spec.ramp.keys.assign(17, RampKey{});
  EXPECT_EQ(error_of(spec).field(), "ramp.keys");
}

TEST(Validated, ChannelsAndRanges) {
  TextureSpec spec = spec_of(NoiseParams{});
  spec.channels = {false, false, false};
  EXPECT_EQ(error_of(spec).field(), "channels");
  spec.channels = {true, true, false};
  spec.opacity = {0.0f, 1.5f};
  EXPECT_EQ(error_of(spec).field(), "opacity.high");
}

TEST(ColourRamp, PiecewiseLinearAndClamped) {
  const ColourRamp ramp{{{0.25f, glm::vec3(0.0f)}, {0.75f, glm::vec3(1.0f)}}};
  EXPECT_EQ(ramp.at(0.0f), glm::vec3(0.0f));
  EXPECT_EQ(ramp.at(0.5f), glm::vec3(0.5f));
  EXPECT_EQ(ramp.at(0.75f), glm::vec3(1.0f));
  EXPECT_EQ(ramp.at(1.0f), glm::vec3(1.0f));
  EXPECT_EQ(ramp.at(std::numeric_limits<float>::quiet_NaN()), glm::vec3(0.0f));
}

TEST(ValidatedVolume, Bounds) {
  Volume v;
  v.max.y = v.min.y;
  EXPECT_EQ(error_of(v).field(), "volume.max.y");
  v = Volume{};
  v.finest_level_log2 = 15;
  const SpecError e = error_of(v);
  EXPECT_EQ(e.field(), "volume.finest_level_log2");
  EXPECT_THAT(e.what(), HasSubstr("[0, 14]"));
  v = Volume{};
  v.min.x = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(error_of(v).field(), "volume.min.x");
}

}  // namespace
}  // namespace soltex
