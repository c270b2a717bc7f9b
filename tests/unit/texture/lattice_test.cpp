#include "soltex/common/lattice.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace soltex {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(SplitLattice, NegativeFractionsUseFloorNotTruncation) {
  const LatticeSplit s = split_lattice(-0.5);
  EXPECT_EQ(s.cell, 255);  // floor(-0.5) = -1 = 255 mod 256
  EXPECT_EQ(s.frac, 0.5f);
}

TEST(SplitLattice, ExactNegativeIntegersHaveZeroFraction) {
  for (int n = -1; n >= -600; --n) {
    const LatticeSplit s = split_lattice(n);
    EXPECT_EQ(s.cell, ((n % 256) + 256) % 256) << n;
    EXPECT_EQ(s.frac, 0.0f) << n;
  }
}

TEST(SplitLattice, ZeroCrossing) {
  EXPECT_EQ(split_lattice(0.0).cell, 0);
  EXPECT_EQ(split_lattice(-0.0).cell, 0);
  EXPECT_EQ(split_lattice(0.25).cell, 0);
  EXPECT_EQ(split_lattice(-0.25).cell, 255);
  EXPECT_EQ(split_lattice(-0.25).frac, 0.75f);
}

TEST(SplitLattice, LargeCoordinatesReduceExactly) {
  EXPECT_EQ(split_lattice(256.25).cell, 0);
  EXPECT_EQ(split_lattice(256.25).frac, 0.25f);
  EXPECT_EQ(split_lattice(8388608.0).cell, 0);  // 2^23
  EXPECT_EQ(split_lattice(1e7).cell, static_cast<int>(10000000 % 256));
  const LatticeSplit above_int = split_lattice(2147483648.5);  // 2^31 + 0.5: past the int range
  EXPECT_EQ(above_int.cell, 0);
  EXPECT_EQ(above_int.frac, 0.5f);
  EXPECT_EQ(split_lattice(1e12 + 3.5).cell, 3);  // 1e12 is a multiple of 256
  EXPECT_EQ(split_lattice(1e12 + 3.5).frac, 0.5f);
  const LatticeSplit negative = split_lattice(-1e12 - 0.25);
  EXPECT_EQ(negative.cell, 255);
  EXPECT_EQ(negative.frac, 0.75f);
  EXPECT_EQ(split_lattice(1e300).cell, 0);
  EXPECT_EQ(split_lattice(-1e300).cell, 0);
}

TEST(SplitLattice, NonFiniteBehavesAsZero) {
  for (double t : {kNaN, kInf, -kInf, 0x1p62, -0x1p62, 1e300}) {
    for (const LatticeSplit s : {split_lattice(t), split_lattice_in_kernel(t)}) {
      EXPECT_EQ(s.cell, 0);
      EXPECT_EQ(std::bit_cast<uint32_t>(s.frac), 0u);
    }
  }
}

TEST(SplitLattice, CellAlwaysInTableRange) {
  for (double t = -1e6; t < 1e6; t += 12345.678) {
    const LatticeSplit s = split_lattice(t);
    EXPECT_GE(s.cell, 0);
    EXPECT_LT(s.cell, 256);
    EXPECT_GE(s.frac, 0.0f);
    EXPECT_LE(s.frac, 1.0f);
  }
  // A tiny negative value: t - floor(t) rounds to 1, the cell is still valid.
  const LatticeSplit tiny = split_lattice(-1e-20);
  EXPECT_EQ(tiny.cell, 255);
  EXPECT_EQ(tiny.frac, 1.0f);
}

// The split's two forms agree bit for bit (cell, and the fraction's bits including the sign
// of zero) on every input the split hands them: |t| < 2^62, no NaN.
void expect_forms_agree(double t) {
  const LatticeSplit floor_form = split_lattice_by_floor(t);
  const LatticeSplit truncation_form = split_lattice_by_truncation(t);
  ASSERT_EQ(truncation_form.cell, floor_form.cell) << std::hexfloat << t;
  ASSERT_EQ(std::bit_cast<uint32_t>(truncation_form.frac), std::bit_cast<uint32_t>(floor_form.frac))
      << std::hexfloat << t;
}

TEST(SplitLattice, TruncationFormEqualsFloorOnEveryFloatInAStride) {
  // One float bit pattern in 251 over all 2^32, both signs, every exponent: zeros,
  // denormals, fractions, integers, past 2^23, 2^31 and 2^52. Patterns beyond the split's
  // range (|t| >= 2^62, Inf, NaN) never reach the forms.
  for (uint64_t bits = 0; bits <= UINT32_MAX; bits += 251) {
    const double t = std::bit_cast<float>(static_cast<uint32_t>(bits));
    if (std::fabs(t) < 0x1p62) expect_forms_agree(t);
  }
}

TEST(SplitLattice, TruncationFormEqualsFloorAroundBoundaries) {
  // 2048 doubles either side of each boundary where the conversion, the fraction or the
  // floor changes behaviour, both signs.
  const double boundaries[] = {0.0,    0x1p-1074, 0x1p-1022, 0x1p-53, 0.5,    1.0,
                               2.0,    255.0,     256.0,     257.0,   0x1p23, 0x1p24,
                               0x1p31, 0x1p32,    0x1p52,    0x1p53,  0x1p61, 0x1p62};
  for (const double boundary : boundaries) {
    for (const double sign : {1.0, -1.0}) {
      double up = sign * boundary, down = sign * boundary;
      for (int step = 0; step < 2048; ++step) {
        if (std::fabs(up) < 0x1p62) expect_forms_agree(up);
        if (std::fabs(down) < 0x1p62) expect_forms_agree(down);
        up = std::nextafter(up, kInf);
        down = std::nextafter(down, -kInf);
      }
    }
  }
  expect_forms_agree(-0.0);
  expect_forms_agree(std::nextafter(0x1p62, 0.0));
  expect_forms_agree(-std::nextafter(0x1p62, 0.0));
}

TEST(SplitLattice, TruncationFormEqualsFloorOnRandomDoubles) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> near(-1000.0, 1000.0);
  for (int n = 0; n < 2'000'000; ++n) {
    expect_forms_agree(near(rng));
    const double any = std::bit_cast<double>(rng());  // every exponent, denormals included
    if (std::fabs(any) < 0x1p62) expect_forms_agree(any);
  }
}

TEST(SplitLattice, NegativeZeroHasPositiveZeroFraction) {
  EXPECT_FALSE(std::signbit(split_lattice(-0.0).frac));
  EXPECT_FALSE(std::signbit(split_lattice_by_truncation(-0.0).frac));
  EXPECT_EQ(split_lattice_by_truncation(-0x1p-1074).cell, 255);
  EXPECT_EQ(split_lattice_by_truncation(-0x1p-1074).frac, 1.0f);
}

TEST(FloorParity, FlooredModuloOfNegatives) {
  EXPECT_EQ(floor_parity(0.0), 0);
  EXPECT_EQ(floor_parity(0.5), 0);
  EXPECT_EQ(floor_parity(1.0), 1);
  EXPECT_EQ(floor_parity(-0.5), 1);
  EXPECT_EQ(floor_parity(-1.0), 1);
  EXPECT_EQ(floor_parity(-2.0), 0);
  EXPECT_EQ(floor_parity(-2.5), 1);
  EXPECT_EQ(floor_parity(-1e-300), 1);
}

TEST(FloorParity, LargeAndNonFinite) {
  EXPECT_EQ(floor_parity(8388608.0), 0);  // 2^23
  EXPECT_EQ(floor_parity(8388609.0), 1);
  EXPECT_EQ(floor_parity(2147483648.5), 0);  // 2^31 + 0.5
  EXPECT_EQ(floor_parity(2147483649.5), 1);
  EXPECT_EQ(floor_parity(1e12), 0);
  EXPECT_EQ(floor_parity(-1e12 - 1), 1);
  EXPECT_EQ(floor_parity(9007199254740994.0), 0);  // 2^53 + 2
  EXPECT_EQ(floor_parity(kNaN), 0);
  EXPECT_EQ(floor_parity(kInf), 0);
  EXPECT_EQ(floor_parity(-kInf), 0);
}

TEST(Fract, InUnitIntervalAndZeroForNonFinite) {
  EXPECT_EQ(fract(-0.25), 0.75);
  EXPECT_EQ(fract(3.5), 0.5);
  EXPECT_EQ(fract(-3.0), 0.0);
  EXPECT_EQ(fract(kNaN), 0.0);
  EXPECT_EQ(fract(kInf), 0.0);
}

}  // namespace
}  // namespace soltex
