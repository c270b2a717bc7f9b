#pragma once

#include <cmath>
#include <cstdint>

// Splitting a texture-space coordinate into an integer lattice cell and a fraction.
//
// Every split goes through floor() in double precision, never an int cast ((int)-0.5 == 0),
// and only a floor the 64-bit integers hold exactly is converted before the reduction by the
// lattice period, so any finite input, however large, yields a valid table index.
namespace soltex {

// The noise lattices repeat every 256 cells along each axis (256-entry tables).
inline constexpr int kLatticePeriod = 256;

struct LatticeSplit {
  int cell;    // floor(t) mod 256, in [0, 255]
  float frac;  // t - floor(t), in [0, 1]; may round up to 1.0f, which continuity makes harmless
};

// Non-finite t (NaN, +-Inf) is treated as 0: a defined value, never an out-of-range index.
// Branch-free (a select, not a jump) so that loops over many coordinates vectorise.
inline LatticeSplit split_lattice(double t) noexcept {
  // Every double of magnitude 2^62 or more is a multiple of 1024: cell 0, fraction 0, which is
  // also what non-finite t gets. One select (NaN compares false) keeps the rest exact: the
  // 64-bit conversion of floor(t) is in range, floor(t) mod 256 is the low byte of that
  // integer in two's complement (also for negative t), and t - floor(t), in [0, 1), is exact
  // in double before its one rounding to float.
  t = std::fabs(t) < 0x1p62 ? t : 0.0;
  const double whole = std::floor(t);
  return {static_cast<int>(static_cast<int64_t>(whole) & 255), static_cast<float>(t - whole)};
}

// fract(u) = u - floor(u), exact for finite u; non-finite u gives 0.
inline double fract(double u) noexcept {
  if (!std::isfinite(u)) return 0.0;
  return u - std::floor(u);
}

// floor(u) mod 2 (floored, so negative u works): 0 or 1. Non-finite u gives 0. Exact for
// every finite double: halving and doubling are exact, and so is the final difference.
inline int floor_parity(double u) noexcept {
  if (!std::isfinite(u)) return 0;
  const double whole = std::floor(u);
  return static_cast<int>(whole - 2.0 * std::floor(whole * 0.5));
}

}  // namespace soltex
