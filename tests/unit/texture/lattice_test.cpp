#include "soltex/common/lattice.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

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
  for (double t : {kNaN, kInf, -kInf}) {
    const LatticeSplit s = split_lattice(t);
    EXPECT_EQ(s.cell, 0);
    EXPECT_EQ(s.frac, 0.0f);
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
