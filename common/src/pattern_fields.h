#pragma once

// The scalar field of each pattern at one point, and along a row of points. The row forms
// call the same inline expressions per point (plus the shared fractal row kernel), so the
// two agree bit for bit.
//
// `box` is the per-axis width of the box (in texture units) over which a hard-edged pattern is
// averaged: a MIP level's spacing on every axis, or a pixel's footprint in the surface's plane.
// Zero on an axis samples the pattern at the point along it.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>

#include "box_filtered_waves.h"
#include "soltex/common/fractal.h"
#include "soltex/common/lattice.h"
#include "soltex/common/texture_spec.h"
#include "soltex/common/value_noise.h"

namespace soltex::fields {

inline double coordinate(const glm::dvec3& p, Axis axis) {
  return p[static_cast<int>(axis)];
}

inline float stripes(const StripesParams& s, const glm::dvec3& p, const glm::dvec3& box) {
  const int axis = static_cast<int>(s.axis);
  return static_cast<float>(
      waves::filtered_parity(s.offset + p[axis] / s.width, box[axis] / s.width));
}

// One axis's +-1 square wave of checker(), averaged over the box's width along that axis.
inline double checker_factor(const CheckerParams& c, int axis, double coordinate, double width) {
  return 1.0 -
         2.0 * waves::filtered_parity(c.offset + coordinate / c.size[axis], width / c.size[axis]);
}

// checker() from its axes' factors, multiplied in the same order. A grid's points share their
// factors along rows and columns, so a brick needs a few dozen factors, not one per point per
// axis.
inline float checker_of_factors(const CheckerParams& c, double fx, double fy, double fz) {
  double sign = 1.0 * fx;
  sign *= fy;
  if (c.three_d) sign *= fz;
  return static_cast<float>(0.5 * (1.0 - sign));
}

// Parity of the cell sum as a product of +-1 square waves, (1 - prod(1 - 2 f_i)) / 2: the box
// average of a product of functions of one axis each is the product of their averages.
inline float checker(const CheckerParams& c, const glm::dvec3& p, const glm::dvec3& box) {
  return checker_of_factors(c, checker_factor(c, 0, p.x, box.x), checker_factor(c, 1, p.y, box.y),
                            c.three_d ? checker_factor(c, 2, p.z, box.z) : 1.0);
}

// The width along the gradient g of a box of per-axis widths `box`: how far a linear function
// with that gradient varies over the box.
inline double width_along(const glm::dvec3& g, const glm::dvec3& box) {
  return std::fabs(g.x) * box.x + std::fabs(g.y) * box.y + std::fabs(g.z) * box.z;
}

// 1 - |2 fract(u) - 1| per axis: a triangle wave, 0 at integers and 1 halfway.
// Each channel depends on one axis alone, so a grid's rows share their red values.
inline float colour_cube_channel(const ColourCubeParams& c, double coordinate, double width) {
  return static_cast<float>(waves::filtered_triangle(coordinate / c.period, width / c.period));
}

inline glm::vec3 colour_cube(const ColourCubeParams& c, const glm::dvec3& p,
                             const glm::dvec3& box) {
  return {colour_cube_channel(c, p.x, box.x), colour_cube_channel(c, p.y, box.y),
          colour_cube_channel(c, p.z, box.z)};
}

// Filtered along the radius; the two ring values are clamped before they are blended, so the
// filtered field stays between them.
inline float rings(const RingsParams& r, const glm::dvec3& p, const glm::dvec3& box) {
  const double radius = std::hypot(p.x, p.y);  // hypot: no overflow for huge coordinates
  const double radial_width = radius > 0.0
                                  ? width_along(glm::dvec3(p.x / radius, p.y / radius, 0.0), box)
                                  : std::max(box.x, box.y);
  const double ring = waves::filtered_parity(radius / r.thickness, radial_width / r.thickness);
  const double inner = std::clamp(r.base, 0.0, 1.0);
  const double outer = std::clamp(r.base + r.amplitude, 0.0, 1.0);
  return static_cast<float>(ring >= 1.0 ? outer : inner + (outer - inner) * ring);
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
                  const glm::dvec3& p, const glm::dvec3& box) {
  const double cy = rotation.cos_y, sy = rotation.sin_y;
  const double cz = frame.cos_tilt_z, sz = frame.sin_tilt_z;
  const double x1 = cy * p.x + sy * p.z;
  const double z1 = -sy * p.x + cy * p.z;
  const double x2 = cz * x1 - sz * p.y;
  const double y2 = sz * x1 + cz * p.y;
  const NoiseTables& tables = noise_tables();
  const double jitter =
      w.jitter *
      (value_noise_in_kernel(tables, glm::dvec3(x2, y2, z1) * w.jitter_scale) - tables.value_mean);
  const double radius = std::hypot(x2, y2);
  const double ring = radius / w.ring_spacing + jitter;
  // The ring's width over the box: the gradient of the radius in the trunk's frame, turned back
  // into texture space. The twist turns the point about y by an angle that grows with y, which
  // moves it by twist * z1 along x1 per unit of y: far from the trunk's axis that outgrows the
  // radius's own change. (The jitter's slope, jitter * jitter_scale at most, is left out.)
  double ring_width = 0.0;
  if (radius > 0.0 && box != glm::dvec3(0.0)) {
    const double ux = x2 / radius, uy = y2 / radius;
    const double along_x1 = ux * cz + uy * sz;  // d radius / d x1
    const glm::dvec3 gradient(along_x1 * cy, uy * cz - ux * sz - along_x1 * w.twist * z1,
                              along_x1 * sy);
    ring_width = width_along(gradient, box) / w.ring_spacing;
  }
  // The dark grain is the thin part of each ring.
  return static_cast<float>(waves::filtered_pulse(ring, w.grain_fraction, ring_width));
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

// The half-width of an even spread with the given variance: sqrt(3) standard deviations.
// ColourRamp::average takes the field's variation within a box in this form.
inline float even_spread(double variance) {
  return std::sqrt(static_cast<float>(3.0 * variance));
}

// A fractal field's spread within the box: the faded octaves' variance, normalised as
// normalise_fractal() normalises the sum.
inline float fractal_spread(const OctavePlan& plan) {
  if (plan.total_weight == 0.0f) return 0.0f;
  const double weight = plan.total_weight;
  double variance = plan.unresolved_variance / (weight * weight);
  if (plan.basis == NoiseBasis::gradient && !plan.absolute) variance *= 0.25;
  return even_spread(variance);
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

// How far the ripple varies over the box: its gradient's extent.
inline double ripple_width(const MarbleParams& m, const glm::dvec3& p, const glm::dvec3& box) {
  if (m.ripple == Ripple::axis) return m.frequency * box[static_cast<int>(m.axis)];
  return width_along(m.frequency * glm::dvec3(p.y * p.z, p.x * p.z, p.x * p.y), box);
}

// undulate(sin(2 pi fract(ripple) + A turb)), mapped to [0, 1]. The ripple is reduced by its
// period before the multiplication by 2 pi, so far-away points keep their precision. Over a
// box the ripple spans 2 pi ripple_width radians, and the box average of sin over a span 2h is
// sin times sin(h) / h: ripples finer than the box fade to the mean, 0.5.
// The box average's factor on the sine, sin(h) / h over the ripple's half span h. A ripple
// along an axis has the same width everywhere on a grid, so a grid makes it once.
inline double marble_fade(double ripple_width) {
  const double half_span = std::numbers::pi * ripple_width;
  if (!(half_span < waves::kMeanWidth)) return 0.0;  // also NaN
  if (half_span > 1e-4) return portable_sin(half_span) / half_span;
  return 1.0;
}

inline double marble_sine(const MarbleParams& m, double ripple_value, float turbulence) {
  const double phase =
      2.0 * std::numbers::pi * fract(ripple_value) + m.amplitude * static_cast<double>(turbulence);
  return portable_sin(phase);
}

inline float marble_of_sine(double sine, double fade) {
  return static_cast<float>(0.5 + 0.5 * (sine * fade));
}

// What the marble field's variance within a box is made of, where s is the sine at the box's
// centre (marble_variance() adds them up). Over the box the ripple's phase runs through a span
// 2h, so sin averages to s sin(h)/h (the fade f1) and sin^2 = (1 - cos 2phase) / 2 to
// (1 - f2 (1 - 2 s^2)) / 2 with f2 = sin(2h)/(2h): the field 0.5 + 0.5 sin varies by
// 0.25 (steady + s^2 by_sine_squared). The faded turbulence octaves move the phase by a
// deviation sigma, which moves the field by 0.5 cos(phase) sigma: 0.25 (1 - s^2) sigma^2.
struct MarbleSpreadTerms {
  double steady;           // (1 - f2) / 2
  double by_sine_squared;  // f2 - f1^2
  double phase_variance;   // (amplitude * the turbulence's unresolved deviation)^2
};

// `turbulence_variance`: the unresolved variance of the turbulence's raw sum.
inline MarbleSpreadTerms marble_spread_terms(const MarbleParams& m, double ripple_width,
                                             double turbulence_variance) {
  const double once = marble_fade(ripple_width);
  const double twice = marble_fade(2.0 * ripple_width);
  const double phase_deviation = m.amplitude * std::sqrt(turbulence_variance);
  return {0.5 * (1.0 - twice), twice - once * once, phase_deviation * phase_deviation};
}

// The field's variance within the box, at most that of a sine's whole period, 1/8; 0 where
// the box is a point or the sine is not finite.
inline double marble_variance(const MarbleSpreadTerms& terms, double sine) {
  const double s2 = sine * sine;
  const double variance =
      0.25 * ((terms.steady + s2 * terms.by_sine_squared) + (1.0 - s2) * terms.phase_variance);
  if (!(variance > 0.0)) return 0.0;
  return variance < 0.125 ? variance : 0.125;
}

inline float marble_spread(const MarbleSpreadTerms& terms, double sine) {
  return even_spread(marble_variance(terms, sine));
}

// What a grid's points share when the ripple follows an axis: its width is the grid's, and so
// are the fade and the spread's terms.
struct MarbleAxisFilter {
  double fade;
  MarbleSpreadTerms terms;
};

inline MarbleAxisFilter marble_axis_filter(const MarbleParams& m, const glm::dvec3& box,
                                           double turbulence_variance) {
  const double width = ripple_width(m, glm::dvec3(0.0), box);
  return {marble_fade(width), marble_spread_terms(m, width, turbulence_variance)};
}

}  // namespace soltex::fields
