#pragma once

// The scalar field of each pattern at one point, and along a row of points. The row forms
// call the same inline expressions per point (plus the shared fractal row kernel), so the
// two agree bit for bit.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>

#include "soltex/common/fractal.h"
#include "soltex/common/lattice.h"
#include "soltex/common/texture_spec.h"
#include "soltex/common/value_noise.h"

namespace soltex::fields {

inline double coordinate(const glm::dvec3& p, Axis axis) {
  return p[static_cast<int>(axis)];
}

inline float stripes(const StripesParams& s, const glm::dvec3& p) {
  return static_cast<float>(floor_parity(s.offset + coordinate(p, s.axis) / s.width));
}

inline float checker(const CheckerParams& c, const glm::dvec3& p) {
  int parity = floor_parity(c.offset + p.x / c.size.x) + floor_parity(c.offset + p.y / c.size.y);
  if (c.three_d) parity += floor_parity(c.offset + p.z / c.size.z);
  return static_cast<float>(parity & 1);
}

// 1 - |2 fract(u) - 1|: a triangle wave, 0 at integers and 1 halfway.
inline float triangle(double u) {
  return static_cast<float>(1.0 - std::fabs(2.0 * fract(u) - 1.0));
}

inline glm::vec3 colour_cube(const ColourCubeParams& c, const glm::dvec3& p) {
  return {triangle(p.x / c.period), triangle(p.y / c.period), triangle(p.z / c.period)};
}

inline float rings(const RingsParams& r, const glm::dvec3& p) {
  // hypot: no overflow for huge coordinates.
  const double ring = floor_parity(std::hypot(p.x, p.y) / r.thickness);
  return static_cast<float>(std::clamp(r.base + r.amplitude * ring, 0.0, 1.0));
}

struct WoodFrame {
  double cos_tilt_z, sin_tilt_z;
};

// The rotation about y depends on y alone, so a row along x computes it once.
struct WoodRotation {
  double cos_y, sin_y;
};

inline WoodRotation wood_rotation(const WoodParams& w, double y) {
  // Rotate the point (not the texture) by -(tilt_y + twist * y) about y, then about z.
  const double angle_y = -(w.tilt_y + w.twist * y);
  return {std::cos(angle_y), std::sin(angle_y)};
}

inline float wood(const WoodParams& w, const WoodFrame& frame, const WoodRotation& rotation,
                  const glm::dvec3& p) {
  const double cy = rotation.cos_y, sy = rotation.sin_y;
  const double x1 = cy * p.x + sy * p.z;
  const double z1 = -sy * p.x + cy * p.z;
  const double x2 = frame.cos_tilt_z * x1 - frame.sin_tilt_z * p.y;
  const double y2 = frame.sin_tilt_z * x1 + frame.cos_tilt_z * p.y;
  const NoiseTables& tables = noise_tables();
  const double jitter =
      w.jitter * (value_noise(tables, glm::dvec3(x2, y2, z1) * w.jitter_scale) - tables.value_mean);
  const double ring = std::hypot(x2, y2) / w.ring_spacing + jitter;
  // The dark grain is the thin part of each ring.
  return fract(ring) < w.grain_fraction ? 1.0f : 0.0f;
}

inline FractalParams single_octave(const NoiseParams& n) {
  return {n.scale, 0, 0, n.basis, true};
}

// Raw fractal sum -> [0, 1]. Signed gradient sums are centred on 0.5.
inline float normalise_fractal(const OctavePlan& plan, float sum) {
  float t = sum / plan.total_weight;
  if (plan.basis == NoiseBasis::gradient && !plan.absolute) t = 0.5f + 0.5f * t;
  return std::clamp(t, 0.0f, 1.0f);
}

inline double ripple(const MarbleParams& m, const glm::dvec3& p) {
  return m.ripple == Ripple::axis ? m.frequency * coordinate(p, m.axis)
                                  : m.frequency * p.x * p.y * p.z;
}

// sin(x) from +, - and * alone: the same bits on every platform and libm, in scalar and
// vectorised loops, at a fraction of libm's cost. Reduced to [-pi/2, pi/2], then the Taylor
// series to x^13, whose truncation error there is below 7e-10 (the result becomes a float).
inline double portable_sin(double x) {
  constexpr double kPi = 3.141592653589793;
  constexpr double kTwoPi = 6.283185307179586;
  constexpr double kHalfPi = 1.5707963267948966;
  double r = x - kTwoPi * std::floor(x * (1.0 / kTwoPi) + 0.5);  // [-pi, pi]
  r = r > kHalfPi ? kPi - r : (r < -kHalfPi ? -kPi - r : r);     // sin(pi - r) = sin(r)
  const double r2 = r * r;
  return r * (1.0 + r2 * (-1.0 / 6.0 +
                          r2 * (1.0 / 120.0 +
                                r2 * (-1.0 / 5040.0 +
                                      r2 * (1.0 / 362880.0 + r2 * (-1.0 / 39916800.0 +
                                                                   r2 * (1.0 / 6227020800.0)))))));
}

// undulate(sin(2 pi fract(ripple) + A turb)), mapped to [0, 1]. The ripple is reduced by its
// period before the multiplication by 2 pi, so far-away points keep their precision.
inline float marble(const MarbleParams& m, double ripple_value, float turbulence) {
  const double phase =
      2.0 * std::numbers::pi * fract(ripple_value) + m.amplitude * static_cast<double>(turbulence);
  return static_cast<float>(0.5 + 0.5 * portable_sin(phase));
}

}  // namespace soltex::fields
