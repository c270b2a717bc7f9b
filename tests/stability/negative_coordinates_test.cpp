// Negative coordinates, exact negative integers and zero crossings: patterns and noise against
// the double-precision reference.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "double_reference.h"
#include "soltex/common/gradient_noise.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/value_noise.h"

namespace soltex {
namespace {

// Value noise: the cell's eight table values are exact floats; the float path rounds the
// three fractions (at most 2^-25 each, times a slope of at most 1) and does seven lerps of
// three operations on values in [0, 1] (each rounding at most 2^-24). Propagated through the
// lerps' convex weights that is at most about 11 * 2^-24 = 6.6e-7.
constexpr double kValueNoiseTolerance = 1e-6;
// Gradient noise: the fade polynomial's intermediates reach 15, where a float step is 2^-20
// (9.5e-7); about three such roundings per fade, three fades, each scaled by differences of
// at most 3 between interpolated values, plus some 30 roundings below 2^-23: under 3e-5.
constexpr double kGradientNoiseTolerance = 3e-5;

// Coordinates around and at zero and negative integers: the cases a cast to int, a floor of
// a negative fraction or a wrap of a negative cell gets wrong.
std::vector<double> hard_coordinates() {
  const double tiny = std::numeric_limits<double>::denorm_min();
  std::vector<double> values = {0.0,    -0.0,   tiny,   -tiny,   1e-300, -1e-300,    1e-17,
                                -1e-17, 0.5,    -0.5,   -1.0,    -1.5,   -2.0,       -255.0,
                                -256.0, -257.0, -511.5, -65536., -1e6,   -1e6 - 0.25};
  for (double integer : {-1.0, -2.0, -256.0, -1e6}) {
    values.push_back(std::nextafter(integer, 0.0));     // just right of it
    values.push_back(std::nextafter(integer, -1e300));  // just left of it
  }
  return values;
}

TEST(NegativeCoordinates, ValueNoiseMatchesTheReference) {
  const std::vector<double> c = hard_coordinates();
  for (double x : c) {
    for (double y : c) {
      for (double z : {0.0, -0.0, -1.0, -0.5, -257.0, 1e-300}) {
        const glm::dvec3 t(x, y, z);
        ASSERT_NEAR(value_noise(t), reference::value_noise(t), kValueNoiseTolerance)
            << x << " " << y << " " << z;
      }
    }
  }
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> negative(-1000.0, 0.0);
  for (int n = 0; n < 100000; ++n) {
    const glm::dvec3 t(negative(rng), negative(rng), negative(rng));
    ASSERT_NEAR(value_noise(t), reference::value_noise(t), kValueNoiseTolerance);
  }
}

TEST(NegativeCoordinates, GradientNoiseMatchesTheReference) {
  const std::vector<double> c = hard_coordinates();
  for (double x : c) {
    for (double y : c) {
      for (double z : {0.0, -0.0, -1.0, -0.5, -257.0, 1e-300}) {
        const glm::dvec3 t(x, y, z);
        ASSERT_NEAR(gradient_noise(t), reference::gradient_noise(t), kGradientNoiseTolerance)
            << x << " " << y << " " << z;
      }
    }
  }
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> negative(-1000.0, 0.0);
  for (int n = 0; n < 100000; ++n) {
    const glm::dvec3 t(negative(rng), negative(rng), negative(rng));
    ASSERT_NEAR(gradient_noise(t), reference::gradient_noise(t), kGradientNoiseTolerance);
  }
}

// At an exact integer the fraction is 0 and the noise is the table value (value basis) or 0
// (gradient basis) of that lattice point, on either side of zero: no cell is folded onto
// its neighbour.
TEST(NegativeCoordinates, ExactNegativeIntegersAreLatticePoints) {
  const auto& tables = noise_tables();
  for (int x = -600; x <= 600; x += 7) {
    for (int y : {-257, -256, -1, 0, 1}) {
      const glm::dvec3 t(x, y, -3.0);
      const int ix = ((x % 256) + 256) % 256, iy = ((y % 256) + 256) % 256;
      EXPECT_EQ(value_noise(t),
                tables.value[static_cast<std::size_t>(reference::hash(ix, iy, 253))])
          << x << " " << y;
      EXPECT_EQ(gradient_noise(t), 0.0f) << x << " " << y;
    }
  }
}

// Noise is continuous: the two sides of zero, and of a negative cell face, differ by the
// slope times the gap (at most 1 per lattice unit for value noise, so nothing here) plus the
// float rounding of each side; a folded cell would jump by up to a whole table value.
TEST(NegativeCoordinates, NoiseIsContinuousAcrossZeroAndNegativeFaces) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-300.0, 300.0);
  for (int n = 0; n < 2000; ++n) {
    const double y = u(rng), z = u(rng);
    for (double face : {0.0, -1.0, -256.0, -1e6}) {
      const glm::dvec3 left(std::nextafter(face, -1e300), y, z), right(face, y, z);
      EXPECT_NEAR(value_noise(left), value_noise(right), 2 * kValueNoiseTolerance);
      EXPECT_NEAR(gradient_noise(left), gradient_noise(right), 2 * kGradientNoiseTolerance);
    }
  }
}

// Periodic in 256 cells on the negative side too: shifting by -256 k changes neither the
// wrapped cell nor the fraction, so the value is the same float. The points are multiples of
// 2^-20, so that t - 256 k is exact in double and the fractions really are the same.
TEST(NegativeCoordinates, NoiseRepeatsEvery256CellsIntoTheNegatives) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(0.0, 256.0);
  const auto grid = [&] { return std::ldexp(std::floor(std::ldexp(u(rng), 20)), -20); };
  for (int n = 0; n < 2000; ++n) {
    const glm::dvec3 t(grid(), grid(), grid());
    for (double k : {1.0, 2.0, 4096.0}) {
      const glm::dvec3 shifted = t - glm::dvec3(256.0 * k);
      EXPECT_EQ(value_noise(shifted), value_noise(t));
      EXPECT_EQ(gradient_noise(shifted), gradient_noise(t));
    }
  }
}

// The band-limited sum at negative points. Raw sum error: each octave's noise error times its
// weight (sum of weights < 2, so < 2 * 6.6e-7), one rounding per octave of the weighted term
// and of the running sum (< 2, so 2^-23 each: 12 * 1.2e-7 for six octaves); over the total
// weight (~2) that is under 1.5e-6, plus the division's 2^-24.
TEST(NegativeCoordinates, TurbulenceMatchesTheReference) {
  TextureSpec spec;
  TurbulenceParams turbulence;
  turbulence.fractal.octave_max = 5;
  spec.pattern = turbulence;
  const TextureEvaluator evaluator(spec);
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> negative(-500.0, 0.0);
  for (double width : {0.0, 0.01, 0.05}) {
    for (int n = 0; n < 20000; ++n) {
      const glm::dvec3 p(negative(rng), negative(rng), negative(rng));
      ASSERT_NEAR(evaluator.sample(p, width).field,
                  reference::turbulence(turbulence.fractal, width, p), 2e-6)
          << p.x << " " << p.y << " " << p.z << " width " << width;
    }
  }
}

// Parity patterns are exact: the field is 0 or 1, so it must equal the reference's parity
// bit for bit, also at exact negative integers, at -0 and next to zero.
TEST(NegativeCoordinates, ParityPatternsEqualTheReferenceExactly) {
  TextureSpec stripes_spec;
  stripes_spec.pattern = StripesParams{0.25, 0.0, Axis::x};
  TextureSpec checker_spec;
  checker_spec.pattern = CheckerParams{glm::dvec3(0.5, 1.0, 2.0), 0.0, true};
  TextureSpec rings_spec;
  rings_spec.pattern = RingsParams{0.1, 0.0, 1.0};
  const TextureEvaluator stripes(stripes_spec), checker(checker_spec), rings(rings_spec);
  std::vector<double> c = hard_coordinates();
  for (int i = -40; i <= 0; ++i) c.push_back(i * 0.25);  // exact multiples of the widths
  for (double x : c) {
    for (double y : c) {
      const glm::dvec3 p(x, y, -0.5 * y);
      EXPECT_EQ(stripes.sample(p).field, reference::parity(x / 0.25)) << x;
      const int cells = reference::parity(x / 0.5) + reference::parity(y / 1.0) +
                        reference::parity(-0.5 * y / 2.0);
      EXPECT_EQ(checker.sample(p).field, cells & 1) << x << " " << y;
      EXPECT_EQ(rings.sample(p).field, reference::parity(std::hypot(x, y) / 0.1)) << x << " " << y;
    }
  }
}

TEST(NegativeCoordinates, StatedValuesAtZeroAndMinusOne) {
  TextureSpec spec;
  spec.pattern = StripesParams{1.0, 0.0, Axis::x};
  const TextureEvaluator stripes(spec);
  // floor(-0) = -0: even, the same stripe as +0.
  EXPECT_EQ(stripes.sample({-0.0, 0.0, 0.0}).field, 0.0f);
  EXPECT_EQ(stripes.sample({0.0, 0.0, 0.0}).field, 0.0f);
  // Anything left of zero is in stripe -1: odd. An int cast would put it in stripe 0.
  EXPECT_EQ(stripes.sample({-1e-300, 0.0, 0.0}).field, 1.0f);
  EXPECT_EQ(stripes.sample({-0.5, 0.0, 0.0}).field, 1.0f);
  EXPECT_EQ(stripes.sample({-1.0, 0.0, 0.0}).field, 1.0f);
  EXPECT_EQ(stripes.sample({std::nextafter(-1.0, -2.0), 0.0, 0.0}).field, 0.0f);
}

// The colour cube's triangle wave, tri(u) = 1 - |2 fract(u) - 1|, against the distance to
// the nearest integer, 2 |u - round(u)|: the same function by another formula. Both are
// within a double rounding of exact; cast to float they agree to one float step (2^-24
// below 1 when the double lies next to a float rounding boundary).
TEST(NegativeCoordinates, ColourCubeMatchesTheReference) {
  TextureSpec spec;
  spec.pattern = ColourCubeParams{0.75};
  const TextureEvaluator cube(spec);
  std::vector<double> c = hard_coordinates();
  for (int i = -40; i <= 0; ++i) c.push_back(i * 0.1875);  // quarter periods
  const auto tri = [](double u) { return 2.0 * std::fabs(u - std::round(u)); };
  for (double x : c) {
    const glm::dvec3 p(x, -x, 0.5 * x);
    const glm::vec3 colour = cube.sample(p).colour;
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(colour[axis], tri(p[axis] / 0.75), std::ldexp(1.0, -24)) << x << " " << axis;
    }
  }
}

}  // namespace
}  // namespace soltex
