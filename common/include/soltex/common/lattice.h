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

// split_lattice(t) for |t| < 2^62 (no NaN) through floor(): the definition.
inline LatticeSplit split_lattice_by_floor(double t) noexcept {
  const double whole = std::floor(t);
  return {static_cast<int>(static_cast<int64_t>(whole) & 255), static_cast<float>(t - whole)};
}

// The same split through the truncating 64-bit conversion and one compare, bit for bit (the
// unit tests check it against split_lattice_by_floor over many inputs):
//   trunc(t) is exact for |t| < 2^62, and floor(t) = trunc(t) - 1 exactly when t < trunc(t);
//   t - trunc(t) is exact (the low bits of t), so adding 1 to it rounds once, to the double
//   nearest t - floor(t), as the definition's one subtraction does;
//   t = -0 gives -0 - +0 = -0, and + 0.0 makes it the definition's +0.
// Without SSE4.1, GCC expands floor() into about a dozen instructions and a branch (its
// range check against 2^52, two conversions, a compare, the sign of zero restored); this is
// half of that, and the cell no longer waits for the fraction.
inline LatticeSplit split_lattice_by_truncation(double t) noexcept {
  const int64_t truncated = static_cast<int64_t>(t);
  const double whole = static_cast<double>(truncated);
  const bool below = t < whole;
  const double fraction = t - whole;
  return {static_cast<int>((truncated - below) & 255),
          static_cast<float>(below ? fraction + 1.0 : fraction + 0.0)};
}

// Every double of magnitude 2^62 or more is a multiple of 1024: cell 0, fraction 0, which is
// also what non-finite t gets. One select (NaN compares false) keeps the rest exact: the
// 64-bit conversion of floor(t) is in range, floor(t) mod 256 is the low byte of that integer
// in two's complement (also for negative t), and t - floor(t), in [0, 1), is exact in double
// before its one rounding to float. Branch-free where the target allows (a select, not a
// jump) so that loops over many coordinates vectorise.
inline double lattice_coordinate(double t) noexcept {
  return std::fabs(t) < 0x1p62 ? t : 0.0;
}

// Non-finite t (NaN, +-Inf) is treated as 0: a defined value, never an out-of-range index.
// For code compiled for the build's static target. Where floor is one instruction (SSE4.1's
// roundsd, every other architecture's own), the definition is the shorter code; only a
// baseline x86-64 build takes the truncation.
inline LatticeSplit split_lattice(double t) noexcept {
#if defined(__x86_64__) && !defined(__SSE4_1__)
  return split_lattice_by_truncation(lattice_coordinate(t));
#else
  return split_lattice_by_floor(lattice_coordinate(t));
#endif
}

// The same split through floor() for code inlined into the runtime-dispatched kernels
// (compiled once per Highway target): the targets chosen on SSE4.1 and AVX machines round in
// one instruction there, which the static target's choice above would not know.
inline LatticeSplit split_lattice_in_kernel(double t) noexcept {
  return split_lattice_by_floor(lattice_coordinate(t));
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
