#include "soltex/common/gradient_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/common.hpp>
#include <limits>
#include <random>

namespace soltex {
namespace {

// Perlin's improved noise written the textbook way, in double: eight corner dot products,
// quintic fade, interpolation along x, then y, then z. The library factors the same function
// differently (per-cell edge coefficients), so agreement checks the factoring.
double reference_gradient_noise(const glm::dvec3& p) {
  static constexpr double gx[16] = {1, -1, 1, -1, 1, -1, 1, -1, 0, 0, 0, 0, 1, -1, 0, 0};
  static constexpr double gy[16] = {1, 1, -1, -1, 0, 0, 0, 0, 1, -1, 1, -1, 1, 1, -1, -1};
  static constexpr double gz[16] = {0, 0, 0, 0, 1, 1, -1, -1, 1, 1, -1, -1, 0, 0, 1, -1};
  const NoiseTables& t = noise_tables();
  const glm::dvec3 cell = glm::floor(p);
  const glm::dvec3 f = p - cell;
  const auto wrap = [](double c) { return static_cast<int>(c - 256.0 * std::floor(c / 256.0)); };
  const int ix = wrap(cell.x), iy = wrap(cell.y), iz = wrap(cell.z);
  const auto fade5 = [](double u) { return u * u * u * (u * (u * 6 - 15) + 10); };
  const auto grad = [&](int dx, int dy, int dz) {
    const int h = t.index(ix + dx, iy + dy, iz + dz) & 15;
    return gx[h] * (f.x - dx) + gy[h] * (f.y - dy) + gz[h] * (f.z - dz);
  };
  const auto lerp = [](double a, double b, double u) { return a + u * (b - a); };
  const double u = fade5(f.x), v = fade5(f.y), w = fade5(f.z);
  const double x00 = lerp(grad(0, 0, 0), grad(1, 0, 0), u);
  const double x10 = lerp(grad(0, 1, 0), grad(1, 1, 0), u);
  const double x01 = lerp(grad(0, 0, 1), grad(1, 0, 1), u);
  const double x11 = lerp(grad(0, 1, 1), grad(1, 1, 1), u);
  return lerp(lerp(x00, x10, v), lerp(x01, x11, v), w);
}

TEST(GradientNoise, MatchesTextbookFormulation) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-600.0, 600.0);
  for (int n = 0; n < 200000; ++n) {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    ASSERT_NEAR(gradient_noise(p), reference_gradient_noise(p), 1e-5)
        << p.x << " " << p.y << " " << p.z;
  }
}

TEST(GradientNoise, ZeroAtLatticePoints) {
  for (int i = -260; i <= 260; i += 13) {
    for (int j : {-257, -1, 0, 3}) {
      for (int k : {-2, 0, 256, 9999}) EXPECT_EQ(gradient_noise(glm::dvec3(i, j, k)), 0.0f);
    }
  }
}

TEST(GradientNoise, BoundedRange) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  float lo = 0.0f, hi = 0.0f;
  for (int n = 0; n < 500000; ++n) {
    const float v = gradient_noise(glm::dvec3(u(rng), u(rng), u(rng)));
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  EXPECT_GT(lo, -1.1f);
  EXPECT_LT(hi, 1.1f);
  EXPECT_LT(lo, -0.6f);  // and it does use its range
  EXPECT_GT(hi, 0.6f);
}

TEST(GradientNoise, PeriodIs256Cells) {
  std::mt19937_64 rng(13);
  std::uniform_int_distribution<int> cell(-1000, 1000);
  for (int n = 0; n < 2000; ++n) {
    const glm::dvec3 p(cell(rng) + 0.625, cell(rng) + 0.1875, cell(rng) + 0.9375);
    EXPECT_EQ(gradient_noise(p), gradient_noise(p + glm::dvec3(256.0, -256.0, 512.0)));
  }
}

TEST(GradientNoise, ContinuousAcrossCells) {
  // |d/dx| of one face term is at most |g| * (1 + fade'max * ...): a loose but sufficient
  // bound of 8 per unit length catches any jump at a cell face.
  const glm::dvec3 direction(0.0, 0.6, 0.8);
  const double h = 1e-3;
  for (double s = -5.0; s < 5.0; s += h) {
    const glm::dvec3 p = glm::dvec3(0.31, 0.0, 0.0) + direction * s;
    ASSERT_LE(std::fabs(gradient_noise(p) - gradient_noise(p + direction * h)), 8.0 * h) << s;
  }
}

TEST(GradientNoise, LargeAndNonFiniteInputsAreDefined) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double big : {8388608.0, 1e7, 2147483648.5, 1e12, -1e12}) {
    const float v = gradient_noise(glm::dvec3(big + 0.25, -big, 0.5));
    EXPECT_TRUE(std::isfinite(v));
    EXPECT_LE(std::fabs(v), 1.1f);
  }
  EXPECT_EQ(gradient_noise(glm::dvec3(nan, inf, -inf)), 0.0f);  // treated as the origin
}

}  // namespace
}  // namespace soltex
