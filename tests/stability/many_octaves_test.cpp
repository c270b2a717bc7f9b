// Turbulence with many octaves: 16 octaves, the most a spec may ask for, up to octave 24.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "double_reference.h"
#include "soltex/common/fractal.h"
#include "soltex/common/spec_error.h"
#include "soltex/common/texture_evaluator.h"

namespace soltex {
namespace {

// For RecordProperty: 3 significant digits in any magnitude (std::to_string prints 1e-7 as 0).
std::string short_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

// 16 octaves ending at the largest octave and frequency the bounds allow:
// 0.6 * 2^24 = 1.007e7 lattice cells per unit, just under 1e4 * 1024.
FractalParams at_the_limits(NoiseBasis basis, bool signed_octaves) {
  FractalParams f;
  f.scale = 0.6;
  f.octave_min = 9;
  f.octave_max = 24;
  f.basis = basis;
  f.signed_octaves = signed_octaves;
  return f;
}

TextureSpec turbulence(const FractalParams& f) {
  TextureSpec spec;
  spec.pattern = TurbulenceParams{f};
  return spec;
}

std::vector<glm::dvec3> points() {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> near(-10.0, 10.0);
  std::vector<glm::dvec3> p;
  for (int n = 0; n < 3000; ++n) p.emplace_back(near(rng), near(rng), near(rng));
  for (int n = 0; n < 1000; ++n) p.push_back(glm::dvec3(-1e6, 1e6, 5e5) + p[n]);
  return p;
}

// Tolerance on the normalised field (sum / total weight): each octave's noise error, weighted
// and divided by the total weight, is at most the one-octave error (value 6.6e-7, gradient
// 3e-5, see negative_coordinates_test.cpp); the running sum is rounded 32 times with a value
// below the total weight (2^-24 of it each: 1.9e-6 in all), and the division once more.
double tolerance(NoiseBasis basis) {
  return (basis == NoiseBasis::value ? 6.6e-7 : 3e-5) + 33.0 * std::ldexp(1.0, -24);
}

TEST(ManyOctaves, SixteenOctavesAreAcceptedAndSeventeenRefused) {
  FractalParams f = at_the_limits(NoiseBasis::value, false);
  EXPECT_NO_THROW(validated(turbulence(f)));
  f.octave_min = 8;
  EXPECT_THROW(validated(turbulence(f)), SpecError);
  f = at_the_limits(NoiseBasis::value, false);
  f.scale = 0.62;  // 0.62 * 2^24 = 1.04e7: beyond the largest frequency
  EXPECT_THROW(validated(turbulence(f)), SpecError);
}

// Expected: every value finite and in [0, 1], and the double reference's within the
// tolerance above, for the value basis, |gradient| and signed gradient, point-sampled and
// band-limited (widths where some, most and all octaves fade).
TEST(ManyOctaves, SixteenOctavesAtTheLimitsMatchTheReference) {
  for (const auto& [basis, signed_octaves] :
       {std::pair{NoiseBasis::value, false}, std::pair{NoiseBasis::gradient, false},
        std::pair{NoiseBasis::gradient, true}}) {
    const FractalParams f = at_the_limits(basis, signed_octaves);
    const TextureEvaluator evaluator(turbulence(f));
    for (double width : {0.0, 1e-7, 1e-5, 1e-3}) {
      double worst = 0.0;
      for (const glm::dvec3& p : points()) {
        const float field = evaluator.sample(p, width).field;
        ASSERT_TRUE(std::isfinite(field));
        ASSERT_GE(field, 0.0f);
        ASSERT_LE(field, 1.0f);
        const double error = std::fabs(field - reference::turbulence(f, width, p));
        worst = std::max(worst, error);
        ASSERT_LE(error, tolerance(basis))
            << "basis " << static_cast<int>(basis) << " signed " << signed_octaves << " width "
            << width << " at " << p.x << " " << p.y << " " << p.z;
      }
      RecordProperty("worst_" + std::to_string(static_cast<int>(basis)) +
                         (signed_octaves ? "_signed_" : "_") + short_number(width),
                     short_number(worst));
    }
  }
}

// In range without the clamp: the raw value-noise sum is a weighted mean of values in
// [0, 1], so sum / total weight may exceed [0, 1] by rounding only.
TEST(ManyOctaves, RawSumStaysWithinItsRange) {
  const FractalParams f = at_the_limits(NoiseBasis::value, false);
  for (double width : {0.0, 1e-6}) {
    const OctavePlan plan = plan_octaves(f, width);
    ASSERT_EQ(plan.count, 16);
    for (const glm::dvec3& p : points()) {
      const double t = fractal_sum(plan, p) / plan.total_weight;
      ASSERT_GE(t, -tolerance(NoiseBasis::value));
      ASSERT_LE(t, 1.0 + tolerance(NoiseBasis::value));
    }
  }
}

// The batch path with 16 octaves at 1e7 cells per unit, where every grid point is in its own
// cell of the finest octaves: bit for bit the single-point path.
TEST(ManyOctaves, BatchEqualsSinglePointBitForBit) {
  const FractalParams f = at_the_limits(NoiseBasis::gradient, false);
  const TextureEvaluator evaluator(turbulence(f));
  Grid grid;
  grid.origin = glm::dvec3(-3.25, 1e6, -2e5);
  grid.step = glm::dvec3(1.3e-4, 7e-5, 2e-3);
  grid.count = glm::ivec3(33, 9, 5);
  grid.first = glm::ivec3(-16, 4, 0);
  for (double width : {0.0, 1e-6}) {
    std::vector<float> out(grid.size() * 3);
    evaluator.evaluate_grid(grid, width, out);
    std::size_t i = 0;
    for (int k = 0; k < grid.count.z; ++k) {
      for (int j = 0; j < grid.count.y; ++j) {
        for (int x = 0; x < grid.count.x; ++x, ++i) {
          const glm::vec3 colour = evaluator.sample(grid.point(x, j, k), width).colour;
          ASSERT_EQ(out[i], colour.r) << x << " " << j << " " << k;
        }
      }
    }
  }
}

}  // namespace
}  // namespace soltex
