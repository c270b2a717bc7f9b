// -march=native may make AVX3_DL the baseline, which Highway then wants among its targets.
#ifndef HWY_WANT_AVX3_DL
#define HWY_WANT_AVX3_DL
#endif
#include "soltex/common/brick_filter.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "soltex/common/brick_codec.h"

namespace soltex {
namespace {

constexpr BrickFilter kFilters[] = {BrickFilter::none, BrickFilter::delta_x,
                                    BrickFilter::gradient_xy, BrickFilter::gradient_3d};

std::vector<uint8_t> random_planes(int side, int planes, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> bytes(static_cast<std::size_t>(side) * side * side * planes);
  for (uint8_t& b : bytes) b = static_cast<uint8_t>(rng());
  return bytes;
}

// The predictors written out sample by sample, as the header comment states them.
std::vector<uint8_t> reference_residuals(BrickFilter filter, int side,
                                         const std::vector<uint8_t>& plane) {
  auto at = [&](int x, int y, int z) -> int {
    if (x < 0 || y < 0 || z < 0) return 0;
    return plane[(static_cast<std::size_t>(z) * side + y) * side + x];
  };
  std::vector<uint8_t> out(plane.size());
  for (int z = 0; z < side; ++z) {
    for (int y = 0; y < side; ++y) {
      for (int x = 0; x < side; ++x) {
        const int a = at(x - 1, y, z), b = at(x, y - 1, z), c = at(x, y, z - 1);
        const int ab = at(x - 1, y - 1, z), ac = at(x - 1, y, z - 1), bc = at(x, y - 1, z - 1);
        const int abc = at(x - 1, y - 1, z - 1);
        int prediction = 0;
        switch (filter) {
          case BrickFilter::none:
            prediction = 0;
            break;
          case BrickFilter::delta_x:
            prediction = a;
            break;
          case BrickFilter::gradient_xy:
            prediction = a + b - ab;
            break;
          case BrickFilter::gradient_3d:
            prediction = a + b + c - ab - ac - bc + abc;
            break;
        }
        out[(static_cast<std::size_t>(z) * side + y) * side + x] =
            static_cast<uint8_t>(at(x, y, z) - prediction);
      }
    }
  }
  return out;
}

TEST(BrickFilter, UndoInvertsApplyForEverySide) {
  for (BrickFilter filter : kFilters) {
    for (int side = 1; side <= 17; ++side) {
      const std::vector<uint8_t> original = random_planes(side, 3, static_cast<uint32_t>(side));
      std::vector<uint8_t> bytes = original;
      apply_brick_filter(filter, side, bytes);
      undo_brick_filter(filter, side, bytes);
      ASSERT_EQ(bytes, original) << brick_filter_name(filter) << " side " << side;
    }
  }
}

TEST(BrickFilter, MatchesThePredictorFormulas) {
  for (BrickFilter filter : kFilters) {
    for (int side : {2, 9, 17}) {
      const std::vector<uint8_t> plane = random_planes(side, 1, 99);
      std::vector<uint8_t> filtered = plane;
      apply_brick_filter(filter, side, filtered);
      EXPECT_EQ(filtered, reference_residuals(filter, side, plane))
          << brick_filter_name(filter) << " side " << side;
    }
  }
}

// An affine field s = 3 + 2x + 5y + 7z (mod 256) is predicted exactly by the 3D
// gradient everywhere off the x = 0, y = 0 and z = 0 faces.
TEST(BrickFilter, Gradient3dPredictsAffineFieldsExactly) {
  const int side = 17;
  std::vector<uint8_t> plane(static_cast<std::size_t>(side) * side * side);
  for (int z = 0; z < side; ++z) {
    for (int y = 0; y < side; ++y) {
      for (int x = 0; x < side; ++x) {
        plane[(static_cast<std::size_t>(z) * side + y) * side + x] =
            static_cast<uint8_t>(3 + 2 * x + 5 * y + 7 * z);
      }
    }
  }
  apply_brick_filter(BrickFilter::gradient_3d, side, plane);
  for (int z = 1; z < side; ++z) {
    for (int y = 1; y < side; ++y) {
      for (int x = 1; x < side; ++x) {
        ASSERT_EQ(plane[(static_cast<std::size_t>(z) * side + y) * side + x], 0)
            << x << " " << y << " " << z;
      }
    }
  }
}

TEST(BrickFilter, PlanesAreFilteredIndependently) {
  const int side = 9;
  const std::vector<uint8_t> two = random_planes(side, 2, 5);
  const std::size_t n = two.size() / 2;
  std::vector<uint8_t> together = two;
  apply_brick_filter(BrickFilter::gradient_3d, side, together);
  std::vector<uint8_t> second(two.begin() + static_cast<std::ptrdiff_t>(n), two.end());
  apply_brick_filter(BrickFilter::gradient_3d, side, second);
  EXPECT_TRUE(
      std::equal(second.begin(), second.end(), together.begin() + static_cast<std::ptrdiff_t>(n)));
}

// Sides above a 16-brick's 17 samples are refused: scratch space is sized for bricks.
TEST(BrickFilter, RejectsBadShapes) {
  std::vector<uint8_t> bytes(10);
  EXPECT_THROW(apply_brick_filter(BrickFilter::delta_x, 0, bytes), std::invalid_argument);
  EXPECT_THROW(apply_brick_filter(BrickFilter::delta_x, 2, bytes), std::invalid_argument);
  EXPECT_THROW(undo_brick_filter(BrickFilter::delta_x, 3, bytes), std::invalid_argument);
  std::vector<uint8_t> too_large(18 * 18 * 18);
  EXPECT_THROW(apply_brick_filter(BrickFilter::delta_x, 18, too_large), std::invalid_argument);
  EXPECT_THROW(apply_brick_filter(static_cast<BrickFilter>(9), 1, bytes), std::invalid_argument);
}

// Floats that probe quantize(): NaN, infinities, values outside [0, 1], exact levels, values
// one float step either side of every rounding boundary (k + 0.5) / 255, and random values.
std::vector<float> quantizer_probes(std::size_t n, uint32_t seed) {
  std::vector<float> probes = {std::numeric_limits<float>::quiet_NaN(),
                               std::numeric_limits<float>::infinity(),
                               -std::numeric_limits<float>::infinity(),
                               -0.0f,
                               0.0f,
                               -1e-30f,
                               1e-30f,
                               1.0f,
                               std::nextafter(1.0f, 0.0f),
                               std::nextafter(1.0f, 2.0f),
                               2.5f,
                               -3.0f};
  for (int k = 0; k < 256; ++k) {
    const float boundary = static_cast<float>((k + 0.5) / 255.0);
    probes.push_back(static_cast<float>(k) / 255.0f);
    probes.push_back(boundary);
    probes.push_back(std::nextafter(boundary, 0.0f));
    probes.push_back(std::nextafter(boundary, 1.0f));
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uniform(-0.1f, 1.1f);
  std::vector<float> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = i < probes.size() ? probes[i] : uniform(rng);
  std::shuffle(out.begin(), out.end(), rng);
  return out;
}

// Every SIMD target this CPU runs gives the bits of the scalar quantize() and
// apply_brick_filter(gradient_3d), and undoes the filter to the same bytes.
TEST(QuantizeAndPredict, EveryTargetMatchesTheScalarFunctions) {
  const std::vector<int64_t> targets = brick_filter_targets();
  ASSERT_FALSE(targets.empty());
  for (int side : {17, 9, 1, 2, 5, 16}) {
    for (int planes : {1, 3, 5}) {
      const std::size_t n = static_cast<std::size_t>(side) * side * side * planes;
      const std::vector<float> samples = quantizer_probes(n, static_cast<uint32_t>(side * planes));
      const std::vector<uint8_t> quantized = quantize(samples);
      std::vector<uint8_t> residual = quantized;
      apply_brick_filter(BrickFilter::gradient_3d, side, residual);
      for (const int64_t target : targets) {
        SCOPED_TRACE(std::string(hwy::TargetName(target)) + " side " + std::to_string(side) + ", " +
                     std::to_string(planes) + " planes");
        hwy::SetSupportedTargetsForTest(target);
        std::vector<uint8_t> q(n + kQuantizePredictSlack), r(n + kQuantizePredictSlack);
        quantize_and_predict(samples, side, q, r);
        EXPECT_TRUE(std::equal(quantized.begin(), quantized.end(), q.begin()));
        EXPECT_TRUE(std::equal(residual.begin(), residual.end(), r.begin()));
        std::vector<uint8_t> values(n);
        quantize_values(samples, values);
        EXPECT_EQ(values, quantized);
        for (BrickFilter filter : kFilters) {
          std::vector<uint8_t> planes_copy = quantized;
          apply_brick_filter(filter, side, planes_copy);
          undo_brick_filter(filter, side, planes_copy);
          EXPECT_EQ(planes_copy, quantized) << brick_filter_name(filter);
        }
      }
      hwy::SetSupportedTargetsForTest(0);
    }
  }
}

TEST(QuantizeAndPredict, RejectsOutputsWithoutTheSlack) {
  const std::vector<float> samples(9 * 9 * 9, 0.25f);
  std::vector<uint8_t> q(samples.size() + kQuantizePredictSlack), r(samples.size());
  EXPECT_THROW(quantize_and_predict(samples, 9, q, r), std::invalid_argument);
  EXPECT_THROW(quantize_and_predict(samples, 18, q, q), std::invalid_argument);
}

}  // namespace
}  // namespace soltex
