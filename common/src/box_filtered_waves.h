#pragma once

// The periodic waves behind the hard-edged patterns, averaged over a box of width w centred on
// u: (I(u + w/2) - I(u - w/2)) / w, with I the wave's integral in closed form. A filtered
// square wave is a difference of its integral, a ramp of triangle-wave shape (Apodaca & Gritz,
// Advanced RenderMan, 2000, "filteredpulsetrain"); pbrt-v3 filters its checkerboard the same
// way (Pharr, Jakob & Humphreys, §10.5.1). As w grows the average tends to the wave's mean, so
// coarse MIP levels and patterns finer than a pixel converge to the mean instead of aliasing.
//
// Every input is reduced by the wave's period first (exactly, as floor_parity and fract do), so
// far-away points keep their precision; a width of 0 (or below kPointWidth, where the
// difference of integrals would lose its precision) gives the point value.

#include <algorithm>
#include <cmath>

#include "soltex/common/lattice.h"

namespace soltex::waves {

// Below this width (in wave units) the box average is the point value to within 1e-7.
inline constexpr double kPointWidth = 1e-9;
// Beyond this width every wave here is its mean to within 1e-8.
inline constexpr double kMeanWidth = 1e8;

// u reduced into [0, period), exactly for every finite u (period a power of two or 1).
inline double reduced(double u, double period) {
  return u - period * std::floor(u / period);
}

// Integral over [0, x] of the square wave floor_parity (0 on [0, 1), 1 on [1, 2)).
inline double square_integral(double x) {
  const double periods = std::floor(x * 0.5);
  return periods + std::max(0.0, x - 2.0 * periods - 1.0);
}

// floor_parity(u) averaged over [u - w/2, u + w/2]: in [0, 1], mean 0.5.
inline double filtered_parity(double u, double w) {
  if (!std::isfinite(u)) return 0.0;
  if (!(w > kPointWidth)) return floor_parity(u);
  if (w >= kMeanWidth) return 0.5;
  const double centre = reduced(u, 2.0);
  const double half = 0.5 * w;
  const double mean = (square_integral(centre + half) - square_integral(centre - half)) / w;
  return std::clamp(mean, 0.0, 1.0);
}

// Integral over [0, x] of the pulse train that is 1 where fract(x) < duty.
inline double pulse_integral(double x, double duty) {
  const double whole = std::floor(x);
  return whole * duty + std::min(x - whole, duty);
}

// (fract(u) < duty ? 1 : 0) averaged over [u - w/2, u + w/2]: in [0, 1], mean duty.
inline double filtered_pulse(double u, double duty, double w) {
  if (!std::isfinite(u)) return 0.0 < duty ? 1.0 : 0.0;
  if (!(w > kPointWidth)) return fract(u) < duty ? 1.0 : 0.0;
  if (w >= kMeanWidth) return duty;
  const double centre = fract(u);
  const double half = 0.5 * w;
  const double mean =
      (pulse_integral(centre + half, duty) - pulse_integral(centre - half, duty)) / w;
  return std::clamp(mean, 0.0, 1.0);
}

// Integral over [0, x] of the triangle wave 1 - |2 fract(x) - 1| (0 at integers, 1 halfway).
inline double triangle_integral(double x) {
  const double whole = std::floor(x);
  const double f = x - whole;
  const double rise = f <= 0.5 ? f * f : 0.5 - (1.0 - f) * (1.0 - f);
  return 0.5 * whole + rise;
}

// The triangle wave averaged over [u - w/2, u + w/2]: in [0, 1], mean 0.5. No edge to blur,
// but a pattern finer than the box must still fade to its mean.
inline double filtered_triangle(double u, double w) {
  if (!(w > kPointWidth)) return 1.0 - std::fabs(2.0 * fract(u) - 1.0);
  if (!std::isfinite(u)) return 0.0;
  if (w >= kMeanWidth) return 0.5;
  const double centre = fract(u);
  const double half = 0.5 * w;
  const double mean = (triangle_integral(centre + half) - triangle_integral(centre - half)) / w;
  return std::clamp(mean, 0.0, 1.0);
}

}  // namespace soltex::waves
