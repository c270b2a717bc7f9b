// The per-point ends of a grid row in vector lanes: the marble field from the row's fractal
// sums, and the colour ramp's lookup into the three colour planes. A brick is 17 x 17 rows of
// 17 points, and both ran point by point after the row's noise was already in lanes.
//
// Highway's "-inl.h" convention (a toggled guard instead of #pragma once): included under
// hwy/foreach_target.h by pattern_kernels.cpp. Every lane executes the scalar path's
// operations in its order (pattern_fields.h's marble() and portable_sin(), ColourRamp::at()),
// Mul then Add, so every target gives the scalar bits; a row's last points that do not fill a
// vector take the scalar functions themselves.

#if defined(SOLTEX_COMMON_GRID_ROW_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SOLTEX_COMMON_GRID_ROW_LANES_INL_H_
#undef SOLTEX_COMMON_GRID_ROW_LANES_INL_H_
#else
#define SOLTEX_COMMON_GRID_ROW_LANES_INL_H_
#endif

#include <hwy/highway.h>

#include <cstddef>
#include <numbers>
#include <vector>

#include "pattern_fields.h"
#include "soltex/common/texture_spec.h"

HWY_BEFORE_NAMESPACE();
namespace soltex::pattern_kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// fields::portable_sin in lanes: the same reduction, selects and Taylor terms.
template <class D>
HWY_INLINE hn::Vec<D> PortableSinLanes(D d, hn::Vec<D> x) {
  constexpr double kPi = 3.141592653589793;
  constexpr double kTwoPi = 6.283185307179586;
  constexpr double kHalfPi = 1.5707963267948966;
  const auto turns = hn::Floor(hn::Add(hn::Mul(x, hn::Set(d, 1.0 / kTwoPi)), hn::Set(d, 0.5)));
  auto r = hn::Sub(x, hn::Mul(hn::Set(d, kTwoPi), turns));
  r = hn::IfThenElse(
      hn::Gt(r, hn::Set(d, kHalfPi)), hn::Sub(hn::Set(d, kPi), r),
      hn::IfThenElse(hn::Lt(r, hn::Set(d, -kHalfPi)), hn::Sub(hn::Set(d, -kPi), r), r));
  const auto r2 = hn::Mul(r, r);
  auto p = hn::Mul(r2, hn::Set(d, 1.0 / 6227020800.0));
  p = hn::Mul(r2, hn::Add(hn::Set(d, -1.0 / 39916800.0), p));
  p = hn::Mul(r2, hn::Add(hn::Set(d, 1.0 / 362880.0), p));
  p = hn::Mul(r2, hn::Add(hn::Set(d, -1.0 / 5040.0), p));
  p = hn::Mul(r2, hn::Add(hn::Set(d, 1.0 / 120.0), p));
  p = hn::Mul(r2, hn::Add(hn::Set(d, -1.0 / 6.0), p));
  return hn::Mul(r, hn::Add(hn::Set(d, 1.0), p));
}

// fields::marble along a row whose ripple follows one axis (so its width, and the fade, is the
// grid's): `field` holds the row's fractal sums on entry and the marble field on exit.
inline void MarbleAxisRow(const MarbleParams& m, const double* xs, double y, double z,
                          const glm::dvec3& box, float* field, std::size_t nx) {
  const double ripple_width = fields::ripple_width(m, glm::dvec3(0.0), box);
  const hn::ScalableTag<double> dd;
  const hn::Rebind<float, decltype(dd)> df;
  const std::size_t lanes = hn::Lanes(dd);
  const auto fade = hn::Set(dd, fields::marble_fade(ripple_width));
  const auto row_ripple = hn::Set(dd, fields::ripple(m, glm::dvec3(0.0, y, z)));
  const auto frequency = hn::Set(dd, m.frequency);
  const auto two_pi = hn::Set(dd, 2.0 * std::numbers::pi);
  const auto amplitude = hn::Set(dd, m.amplitude);
  const auto half = hn::Set(dd, 0.5);
  const bool along_x = m.axis == Axis::x;
  std::size_t i = 0;
  for (; i + lanes <= nx; i += lanes) {
    const auto ripple = along_x ? hn::Mul(frequency, hn::LoadU(dd, xs + i)) : row_ripple;
    // fract(): u - floor(u), which is NaN exactly where u is not finite; fract gives 0 there.
    const auto whole = hn::Sub(ripple, hn::Floor(ripple));
    const auto fraction = hn::IfThenZeroElse(hn::IsNaN(whole), whole);
    const auto turbulence = hn::PromoteTo(dd, hn::LoadU(df, field + i));
    const auto phase = hn::Add(hn::Mul(two_pi, fraction), hn::Mul(amplitude, turbulence));
    const auto value = hn::Add(half, hn::Mul(half, hn::Mul(PortableSinLanes(dd, phase), fade)));
    hn::StoreU(hn::DemoteTo(df, value), df, field + i);
  }
  for (; i < nx; ++i) {
    const glm::dvec3 p(xs[i], y, z);
    field[i] = fields::marble(m, fields::ripple(m, p), field[i], ripple_width);
  }
}

// ColourRamp::at for a row of fields, into three colour planes. The first key at or above t
// decides in at(); here the keys are visited from the last down, each overriding the lanes it
// covers, so the lowest such key is the one left. Needs at least one key.
inline void RampRow(const ColourRamp& ramp, const float* t, std::size_t nx, float* red,
                    float* green, float* blue) {
  const std::vector<RampKey>& keys = ramp.keys;
  const hn::ScalableTag<float> df;
  const std::size_t lanes = hn::Lanes(df);
  float* planes[3] = {red, green, blue};
  std::size_t i = 0;
  for (; i + lanes <= nx; i += lanes) {
    const auto tv = hn::LoadU(df, t + i);
    hn::Vec<decltype(df)> colour[3];
    for (int c = 0; c < 3; ++c) colour[c] = hn::Set(df, keys.back().colour[c]);
    for (std::size_t k = keys.size() - 1; k >= 1; --k) {
      const RampKey& hi = keys[k];
      const RampKey& lo = keys[k - 1];
      const auto at_hi = hn::Eq(tv, hn::Set(df, hi.position));
      const auto covered = hn::Le(tv, hn::Set(df, hi.position));
      const auto u =
          hn::Div(hn::Sub(tv, hn::Set(df, lo.position)), hn::Set(df, hi.position - lo.position));
      for (int c = 0; c < 3; ++c) {
        const auto mixed = hn::Add(hn::Set(df, lo.colour[c]),
                                   hn::Mul(u, hn::Set(df, hi.colour[c] - lo.colour[c])));
        const auto value = hn::IfThenElse(at_hi, hn::Set(df, hi.colour[c]), mixed);
        colour[c] = hn::IfThenElse(covered, value, colour[c]);
      }
    }
    // !(t > first key): the first key's colour, NaN included.
    const auto below = hn::Not(hn::Gt(tv, hn::Set(df, keys.front().position)));
    for (int c = 0; c < 3; ++c) {
      colour[c] = hn::IfThenElse(below, hn::Set(df, keys.front().colour[c]), colour[c]);
      hn::StoreU(colour[c], df, planes[c] + i);
    }
  }
  for (; i < nx; ++i) {
    const glm::vec3 c = ramp.at(t[i]);
    red[i] = c.r;
    green[i] = c.g;
    blue[i] = c.b;
  }
}

}  // namespace soltex::pattern_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // SOLTEX_COMMON_GRID_ROW_LANES_INL_H_
