// specular_power() against std::pow over the range the lighting uses it in.
#include "specular_power.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace soltex {
namespace {

using render_internal::exp2_of;
using render_internal::log2_of_positive;
using render_internal::specular_power;

TEST(SpecularPower, MatchesPowWhereTheResultIsANormalFloat) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_real_distribution<float> log_exponent(0.0f, 4.0f);  // 1 .. 10000
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const float x = i < 1000 ? 1.0f - static_cast<float>(i) * 1e-7f : unit(random);
    if (!(x > 0.0f)) continue;
    const auto exponent = static_cast<float>(std::pow(10.0, log_exponent(random)));
    const double exact = std::pow(static_cast<double>(x), static_cast<double>(exponent));
    if (exact < 1e-30) continue;
    const double error = std::abs(specular_power(x, exponent) - exact) / exact;
    worst = std::max(worst, error);
  }
  EXPECT_LT(worst, 2e-5);
}

TEST(SpecularPower, TypicalShininessOnAFineGrid) {
  double worst = 0.0;
  for (int i = 1; i <= 100000; ++i) {
    const float x = static_cast<float>(i) / 100000.0f;
    for (const float exponent : {1.0f, 8.0f, 32.0f, 60.0f}) {
      const double exact = std::pow(static_cast<double>(x), static_cast<double>(exponent));
      if (exact < 1e-30) continue;
      worst = std::max(worst, std::abs(specular_power(x, exponent) - exact) / exact);
    }
  }
  EXPECT_LT(worst, 2e-5);
}

TEST(SpecularPower, EdgesAreExactOrZero) {
  EXPECT_EQ(specular_power(1.0f, 60.0f), 1.0f);
  EXPECT_EQ(exp2_of(0.0f), 1.0f);
  EXPECT_EQ(exp2_of(-126.5f), 0.0f);
  EXPECT_EQ(exp2_of(-1000.0f), 0.0f);
  EXPECT_EQ(specular_power(1e-30f, 10000.0f), 0.0f);
  EXPECT_EQ(specular_power(std::numeric_limits<float>::denorm_min(), 1.0f),
            std::numeric_limits<float>::min())
      << "subnormals count as the smallest normal";
  EXPECT_EQ(log2_of_positive(0.5f), -1.0f);
  EXPECT_EQ(log2_of_positive(0.25f), -2.0f);
  for (int n = -126; n <= 0; ++n) {
    EXPECT_FLOAT_EQ(exp2_of(static_cast<float>(n)), std::ldexp(1.0f, n)) << n;
  }
  // NaN (a lane the batch discards) gives a number, not undefined behaviour.
  EXPECT_FALSE(std::isnan(exp2_of(std::numeric_limits<float>::quiet_NaN())));
}

}  // namespace
}  // namespace soltex
