#include "soltex/common/fractal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "soltex/common/gradient_noise.h"
#include "soltex/common/value_noise.h"

namespace soltex {
namespace {

FractalParams six_octaves(NoiseBasis basis, bool signed_octaves = false) {
  return {4.0, 0, 5, basis, signed_octaves};
}

TEST(PlanOctaves, PointSamplingKeepsEveryOctave) {
  const OctavePlan plan = plan_octaves(six_octaves(NoiseBasis::value), 0.0);
  ASSERT_EQ(plan.count, 6);
  EXPECT_EQ(plan.evaluated_octaves(), 6);
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(plan.octaves[k].frequency, 4.0 * std::ldexp(1.0, k));
    EXPECT_EQ(plan.octaves[k].noise_weight, std::ldexp(1.0f, -k));
    EXPECT_EQ(plan.octaves[k].mean_term, 0.0f);
  }
  EXPECT_FLOAT_EQ(plan.total_weight, 1.96875f);
}

TEST(PlanOctaves, OctavesPastNyquistAreReplacedByTheirMean) {
  // Frequencies 4, 8, ..., 128 cells per unit; width 1/64: f * w = 1/16 ... 2.
  const OctavePlan plan = plan_octaves(six_octaves(NoiseBasis::value), 1.0 / 64.0);
  const float mean = noise_tables().value_mean;
  for (int k = 0; k < plan.count; ++k) {
    const double cells_per_sample = plan.octaves[k].frequency / 64.0;
    const float weight = std::ldexp(1.0f, -k);
    if (cells_per_sample <= 0.25) {
      EXPECT_EQ(plan.octaves[k].noise_weight, weight) << k;
      EXPECT_EQ(plan.octaves[k].mean_term, 0.0f) << k;
    } else if (cells_per_sample >= 0.5) {
      EXPECT_EQ(plan.octaves[k].noise_weight, 0.0f) << k;
      EXPECT_FLOAT_EQ(plan.octaves[k].mean_term, weight * mean) << k;
    }
  }
  EXPECT_EQ(plan.evaluated_octaves(), 3);  // f*w = 1/16, 1/8, 1/4 present; 1/2, 1, 2 gone
}

TEST(PlanOctaves, CoarserSpacingEvaluatesFewerOctaves) {
  int previous = 99;
  for (double width = 1e-4; width < 10.0; width *= 2.0) {
    const int n = plan_octaves(six_octaves(NoiseBasis::gradient), width).evaluated_octaves();
    EXPECT_LE(n, previous);
    previous = n;
  }
  EXPECT_EQ(previous, 0);
}

TEST(FractalSum, IsTheLectureTurbulenceAtPointSampling) {
  // Turb(s, p, n1, n2) = sum_{k=n1}^{n2} (1/2)^k noise(2^k s p)
  const FractalParams params{2.5, 1, 4, NoiseBasis::value, false};
  const OctavePlan plan = plan_octaves(params, 0.0);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  for (int n = 0; n < 10000; ++n) {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    double expected = 0.0;
    for (int k = 1; k <= 4; ++k)
      expected += std::ldexp(1.0, -k) * value_noise(p * std::ldexp(2.5, k));
    ASSERT_NEAR(fractal_sum(plan, p), expected, 1e-6);
  }
}

TEST(FractalSum, GradientTurbulenceFoldsOctaves) {
  const OctavePlan plan = plan_octaves(six_octaves(NoiseBasis::gradient), 0.0);
  const OctavePlan signed_plan = plan_octaves(six_octaves(NoiseBasis::gradient, true), 0.0);
  const glm::dvec3 p(0.37, -1.21, 2.03);
  double folded = 0.0, plain = 0.0;
  for (int k = 0; k < 6; ++k) {
    const float n = gradient_noise(p * std::ldexp(4.0, k));
    folded += std::ldexp(1.0, -k) * std::fabs(n);
    plain += std::ldexp(1.0, -k) * n;
  }
  EXPECT_NEAR(fractal_sum(plan, p), folded, 1e-6);
  EXPECT_NEAR(fractal_sum(signed_plan, p), plain, 1e-6);
}

TEST(FractalSum, RowIsBitIdenticalToSinglePoint) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (NoiseBasis basis : {NoiseBasis::value, NoiseBasis::gradient}) {
    for (bool signed_octaves : {false, true}) {
      for (double width : {0.0, 1.0 / 100.0, 1.0 / 20.0}) {
        for (double origin : {0.0, -7.3, 1e6 + 0.1, -1e9}) {
          const OctavePlan plan = plan_octaves(six_octaves(basis, signed_octaves), width);
          std::vector<double> x(97);
          const double step = 0.0123;
          for (std::size_t i = 0; i < x.size(); ++i) x[i] = origin + static_cast<double>(i) * step;
          std::vector<float> row(x.size());
          const double y = origin + u(rng), z = u(rng);
          fractal_sum_row(plan, x, y, z, row);
          for (std::size_t i = 0; i < x.size(); ++i) {
            ASSERT_EQ(row[i], fractal_sum(plan, glm::dvec3(x[i], y, z)))
                << "basis " << int(basis) << " width " << width << " origin " << origin << " i "
                << i;
          }
        }
      }
    }
  }
}

TEST(FractalSum, GradientAbsMeanConstantIsMeasured) {
  // The constant that replaces faded |gradient| octaves must be the actual mean.
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(0.0, 256.0);
  double sum = 0.0;
  const int n = 1 << 20;
  for (int i = 0; i < n; ++i) sum += std::fabs(gradient_noise(glm::dvec3(u(rng), u(rng), u(rng))));
  EXPECT_NEAR(sum / n, kGradientAbsMean, 0.002);
}

TEST(FractalSum, BasisVarianceConstantsAreMeasured) {
  // The variances that size a faded octave's share of a box's spread must be the actual ones.
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<double> u(0.0, 256.0);
  double value = 0.0, value2 = 0.0, gradient2 = 0.0, absolute = 0.0;
  const int n = 1 << 20;
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    const double v = value_noise(p), g = gradient_noise(p);
    value += v;
    value2 += v * v;
    gradient2 += g * g;
    absolute += std::fabs(g);
  }
  const double value_mean = value / n, absolute_mean = absolute / n;
  EXPECT_NEAR(value2 / n - value_mean * value_mean, kValueNoiseVariance, 3e-4);
  EXPECT_NEAR(gradient2 / n, kGradientVariance, 6e-4);
  EXPECT_NEAR(gradient2 / n - absolute_mean * absolute_mean, kGradientAbsVariance, 3e-4);
}

TEST(FractalSum, FadedOctavesAddTheirVarianceToThePlan) {
  const FractalParams fractal{4.0, 0, 5, NoiseBasis::value, false};
  EXPECT_EQ(plan_octaves(fractal, 0.0).unresolved_variance, 0.0);
  // Every octave gone: the weights' squares times the basis variance.
  double all = 0.0;
  for (int k = 0; k <= 5; ++k) all += std::ldexp(1.0, -2 * k) * kValueNoiseVariance;
  EXPECT_NEAR(plan_octaves(fractal, 10.0).unresolved_variance, all, 1e-9);
  const double some = plan_octaves(fractal, 1.0 / 64.0).unresolved_variance;
  EXPECT_GT(some, 0.0);
  EXPECT_LT(some, all);
}

TEST(FractalSum, ManyOctavesAndHugeInputsStayFinite) {
  const FractalParams many{1.0, 8, 23, NoiseBasis::gradient, false};
  const OctavePlan plan = plan_octaves(many, 0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double big : {8388608.0, 1e7, 2147483648.5, 1e12, -1e12, nan, inf, -inf}) {
    const float v = fractal_sum(plan, glm::dvec3(big, 0.5, -big));
    EXPECT_TRUE(std::isfinite(v)) << big;
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, plan.total_weight * 1.1f);
  }
}

}  // namespace
}  // namespace soltex
