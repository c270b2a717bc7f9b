#include "soltex/common/value_noise.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>

namespace soltex {
namespace {

const NoiseTables& T() {
  return noise_tables();
}

float lattice_value(int i, int j, int k) {
  return T().value[T().index(i & 255, j & 255, k & 255)];
}

TEST(NoiseTables, PermutationAndRange) {
  std::array<int, 256> seen{};
  for (int i = 0; i < 256; ++i) {
    ++seen[T().perm[i]];
    EXPECT_EQ(T().perm[i], T().perm[i + 256]);
    EXPECT_GE(T().value[i], 0.0f);
    EXPECT_LE(T().value[i], 1.0f);
  }
  for (int count : seen) EXPECT_EQ(count, 1);
}

TEST(NoiseTables, ReproducibleFromTheSeed) {
  const NoiseTables again = make_noise_tables(kNoiseSeed);
  EXPECT_EQ(again.value, T().value);
  EXPECT_EQ(again.perm, T().perm);
  const NoiseTables other = make_noise_tables(kNoiseSeed + 1);
  EXPECT_NE(other.value, T().value);
}

TEST(NoiseTables, GoldenValuesPinTheTextureDefinition) {
  // Changing the seed, the generator or the table layout changes every noise texture; these
  // values make such a change visible.
  EXPECT_EQ(T().perm[0], 77);
  EXPECT_EQ(T().perm[1], 207);
  EXPECT_EQ(T().perm[255], 254);
  EXPECT_FLOAT_EQ(T().value[0], 0.82201099f);
  EXPECT_FLOAT_EQ(T().value[255], 0.2729083f);
}

TEST(ValueNoise, EqualsTableAtLatticePoints) {
  for (int i = -300; i <= 300; i += 37) {
    for (int j = -5; j <= 5; ++j) {
      for (int k : {-256, -1, 0, 1, 255, 256, 1000}) {
        EXPECT_EQ(value_noise(glm::dvec3(i, j, k)), lattice_value(i, j, k))
            << i << "," << j << "," << k;
      }
    }
  }
}

TEST(ValueNoise, InUnitRange) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1000.0, 1000.0);
  for (int n = 0; n < 100000; ++n) {
    const float v = value_noise(glm::dvec3(u(rng), u(rng), u(rng)));
    ASSERT_GE(v, 0.0f);
    ASSERT_LE(v, 1.0f);
  }
}

TEST(ValueNoise, PeriodIs256CellsOnEveryAxis) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> cell(-2000, 2000);
  for (int n = 0; n < 2000; ++n) {
    // Dyadic fractions: p and p + 256 have the same fraction exactly.
    const glm::dvec3 p(cell(rng) + 0.375, cell(rng) + 0.8125, cell(rng) + 0.0625);
    const float v = value_noise(p);
    EXPECT_EQ(v, value_noise(p + glm::dvec3(256.0, 0.0, 0.0)));
    EXPECT_EQ(v, value_noise(p + glm::dvec3(0.0, -512.0, 0.0)));
    EXPECT_EQ(v, value_noise(p + glm::dvec3(0.0, 0.0, 256.0 * 1000)));
  }
}

TEST(ValueNoise, LipschitzContinuousAcrossCells) {
  // Each axis derivative of a trilinear interpolant of values in [0, 1] is at most 1, so along
  // a unit direction the change is at most sqrt(3) per unit length (plus float rounding).
  const glm::dvec3 direction = glm::dvec3(0.48, 0.6, 0.64);  // unit length
  const double h = 1e-3;
  for (double s = -3.0 * std::sqrt(3.0); s < 3.0 * std::sqrt(3.0); s += h) {
    const glm::dvec3 p = direction * s;
    const float a = value_noise(p);
    const float b = value_noise(p + direction * h);
    ASSERT_LE(std::fabs(a - b), std::sqrt(3.0) * h + 1e-6) << "at s = " << s;
  }
  for (int n = -3; n <= 3; ++n) {
    const glm::dvec3 below(n - 1e-9, 0.3, -0.7), above(n + 1e-9, 0.3, -0.7);
    EXPECT_NEAR(value_noise(below), value_noise(above), 1e-6) << "across x = " << n;
  }
}

TEST(ValueNoise, MeanOverOnePeriodIsTheTableMean) {
  // Every lattice value weighs the same in the integral, and each x-row of one period visits
  // every table entry once: the row sums equal the table sum.
  const double table_sum = std::accumulate(T().value.begin(), T().value.end(), 0.0);
  EXPECT_NEAR(T().value_mean, table_sum / 256.0, 1e-7);
  for (int j : {0, 17, 255}) {
    for (int k : {0, 99, 200}) {
      double row = 0.0;
      for (int i = 0; i < 256; ++i) row += lattice_value(i, j, k);
      EXPECT_NEAR(row, table_sum, 1e-9);
    }
  }
}

TEST(ValueNoise, LargeAndNonFiniteInputsAreDefined) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double big : {8388608.0, 1e7, 2147483648.5, 1e12, -1e12, 1e300}) {
    const float v = value_noise(glm::dvec3(big, -big, 0.5 * big));
    EXPECT_TRUE(std::isfinite(v));
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 1.0f);
  }
  // Documented: a non-finite coordinate is treated as 0.
  EXPECT_EQ(value_noise(glm::dvec3(nan, 0.5, 0.25)), value_noise(glm::dvec3(0.0, 0.5, 0.25)));
  EXPECT_EQ(value_noise(glm::dvec3(0.5, inf, -inf)), value_noise(glm::dvec3(0.5, 0.0, 0.0)));
}

// The kernels' form (floor through split_lattice_in_kernel) gives the static form's bits.
TEST(ValueNoise, KernelFormEqualsStaticForm) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> coordinate(-600.0, 600.0);
  for (int n = 0; n < 20000; ++n) {
    const glm::dvec3 t(coordinate(rng), coordinate(rng), coordinate(rng));
    ASSERT_EQ(std::bit_cast<uint32_t>(value_noise_in_kernel(noise_tables(), t)),
              std::bit_cast<uint32_t>(value_noise(noise_tables(), t)))
        << t.x << " " << t.y << " " << t.z;
  }
  const glm::dvec3 odd(-0.0, -1e-300, -3.0);
  EXPECT_EQ(std::bit_cast<uint32_t>(value_noise_in_kernel(noise_tables(), odd)),
            std::bit_cast<uint32_t>(value_noise(noise_tables(), odd)));
}

}  // namespace
}  // namespace soltex
