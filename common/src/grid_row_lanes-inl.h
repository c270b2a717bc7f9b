// The per-point ends of a grid row in vector lanes: the marble field and its spread from the
// row's fractal sums, the wood field (its jitter's value noise gathered per lane), and the
// colour ramp, at points or averaged over their spreads, into the three colour planes (over a
// whole grid at once). A brick is 17 x 17 rows of 17 points, and all of these ran point by
// point, the marble's after the row's noise was already in lanes.
//
// Highway's "-inl.h" convention (a toggled guard instead of #pragma once): included under
// hwy/foreach_target.h by pattern_kernels.cpp. Every lane executes the scalar path's
// operations in its order (pattern_fields.h's marble_sine(), marble_of_sine(),
// marble_variance(), even_spread(), portable_sin() and wood(), value_noise.h,
// box_filtered_waves.h's filtered_pulse(), ColourRamp::at() and average()), Mul then Add, so
// every target gives the scalar bits; the last points that do not fill a vector take the
// scalar functions themselves, and std::hypot stays the library's, called per point.

#if defined(SOLTEX_COMMON_GRID_ROW_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SOLTEX_COMMON_GRID_ROW_LANES_INL_H_
#undef SOLTEX_COMMON_GRID_ROW_LANES_INL_H_
#else
#define SOLTEX_COMMON_GRID_ROW_LANES_INL_H_
#endif

#include <hwy/highway.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <vector>

#include "box_filtered_waves.h"
#include "pattern_fields.h"
#include "soltex/common/noise_tables.h"
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

// The marble field along a row whose ripple follows one axis (so its width, the fade and the
// spread's terms are the grid's, in `filter`): `field` holds the row's fractal sums on entry
// and the marble field on exit, `spread` receives fields::marble_spread.
inline void MarbleAxisRow(const MarbleParams& m, const fields::MarbleAxisFilter& filter,
                          const double* xs, double y, double z, float* field, float* spread,
                          std::size_t nx) {
  const fields::MarbleSpreadTerms& terms = filter.terms;
  const hn::ScalableTag<double> dd;
  const hn::Rebind<float, decltype(dd)> df;
  const std::size_t lanes = hn::Lanes(dd);
  const auto fade = hn::Set(dd, filter.fade);
  const auto row_ripple = hn::Set(dd, fields::ripple(m, glm::dvec3(0.0, y, z)));
  const auto frequency = hn::Set(dd, m.frequency);
  const auto two_pi = hn::Set(dd, 2.0 * std::numbers::pi);
  const auto amplitude = hn::Set(dd, m.amplitude);
  const auto half = hn::Set(dd, 0.5);
  const auto one = hn::Set(dd, 1.0);
  const auto steady = hn::Set(dd, terms.steady);
  const auto by_sine_squared = hn::Set(dd, terms.by_sine_squared);
  const auto phase_variance = hn::Set(dd, terms.phase_variance);
  const auto largest_variance = hn::Set(dd, 0.125);
  const bool along_x = m.axis == Axis::x;
  std::size_t i = 0;
  for (; i + lanes <= nx; i += lanes) {
    const auto ripple = along_x ? hn::Mul(frequency, hn::LoadU(dd, xs + i)) : row_ripple;
    // fract(): u - floor(u), which is NaN exactly where u is not finite; fract gives 0 there.
    const auto whole = hn::Sub(ripple, hn::Floor(ripple));
    const auto fraction = hn::IfThenZeroElse(hn::IsNaN(whole), whole);
    const auto turbulence = hn::PromoteTo(dd, hn::LoadU(df, field + i));
    const auto phase = hn::Add(hn::Mul(two_pi, fraction), hn::Mul(amplitude, turbulence));
    const auto sine = PortableSinLanes(dd, phase);
    const auto value = hn::Add(half, hn::Mul(half, hn::Mul(sine, fade)));
    hn::StoreU(hn::DemoteTo(df, value), df, field + i);
    const auto s2 = hn::Mul(sine, sine);
    const auto variance =
        hn::Mul(hn::Set(dd, 0.25), hn::Add(hn::Add(steady, hn::Mul(s2, by_sine_squared)),
                                           hn::Mul(hn::Sub(one, s2), phase_variance)));
    const auto capped =
        hn::IfThenElse(hn::Lt(variance, largest_variance), variance, largest_variance);
    const auto kept = hn::IfThenElseZero(hn::Gt(variance, hn::Zero(dd)), capped);
    hn::StoreU(hn::Sqrt(hn::DemoteTo(df, hn::Mul(hn::Set(dd, 3.0), kept))), df, spread + i);
  }
  for (; i < nx; ++i) {
    const glm::dvec3 p(xs[i], y, z);
    const double sine = fields::marble_sine(m, fields::ripple(m, p), field[i]);
    field[i] = fields::marble_of_sine(sine, filter.fade);
    spread[i] = fields::marble_spread(terms, sine);
  }
}

// split_lattice_in_kernel per lane: the cell as int32 and the fraction as float, in the float
// lanes that pair with `d`'s doubles. floor(t) mod 256 is computed in double (exact: scaling by
// 256 and flooring are exact, and the difference is an integer in [0, 255]), which is the low
// byte of the definition's 64-bit integer.
template <class D>
struct LatticeLanes {
  hn::Vec<hn::Rebind<int32_t, D>> cell;
  hn::Vec<hn::Rebind<float, D>> frac;
};

template <class D>
HWY_INLINE LatticeLanes<D> SplitLatticeLanes(D d, hn::Vec<D> t) {
  const hn::Rebind<int32_t, D> di;
  const hn::Rebind<float, D> df;
  const auto inside = hn::IfThenElseZero(hn::Lt(hn::Abs(t), hn::Set(d, 0x1p62)), t);
  const auto whole = hn::Floor(inside);
  const auto periods = hn::Floor(hn::Mul(whole, hn::Set(d, 1.0 / kLatticePeriod)));
  const auto cell =
      hn::Sub(whole, hn::Mul(hn::Set(d, static_cast<double>(kLatticePeriod)), periods));
  return {hn::DemoteTo(di, cell), hn::DemoteTo(df, hn::Sub(inside, whole))};
}

// value_noise_in_kernel per lane: the row hashes and the eight corners gathered.
template <class D>
HWY_INLINE hn::Vec<hn::Rebind<float, D>> ValueNoiseLanes(D d, const NoiseTables& tables,
                                                         hn::Vec<D> tx, hn::Vec<D> ty,
                                                         hn::Vec<D> tz) {
  const hn::Rebind<int32_t, D> di;
  const hn::Rebind<float, D> df;
  const LatticeLanes<D> x = SplitLatticeLanes(d, tx);
  const LatticeLanes<D> y = SplitLatticeLanes(d, ty);
  const LatticeLanes<D> z = SplitLatticeLanes(d, tz);
  const int32_t* perm = tables.perm.data();
  const auto one = hn::Set(di, 1);
  const auto pz0 = hn::GatherIndex(di, perm, z.cell);
  const auto pz1 = hn::GatherIndex(di, perm, hn::Add(z.cell, one));
  const auto y1 = hn::Add(y.cell, one);
  const auto h00 = hn::GatherIndex(di, perm, hn::Add(y.cell, pz0));
  const auto h10 = hn::GatherIndex(di, perm, hn::Add(y1, pz0));
  const auto h01 = hn::GatherIndex(di, perm, hn::Add(y.cell, pz1));
  const auto h11 = hn::GatherIndex(di, perm, hn::Add(y1, pz1));
  const float* v = tables.value_at.data();
  const auto face = [&](hn::Vec<decltype(di)> ix) {
    const auto c00 = hn::GatherIndex(df, v, hn::Add(ix, h00));
    const auto c10 = hn::GatherIndex(df, v, hn::Add(ix, h10));
    const auto c01 = hn::GatherIndex(df, v, hn::Add(ix, h01));
    const auto c11 = hn::GatherIndex(df, v, hn::Add(ix, h11));
    const auto a = hn::Add(c00, hn::Mul(y.frac, hn::Sub(c10, c00)));
    const auto b = hn::Add(c01, hn::Mul(y.frac, hn::Sub(c11, c01)));
    return hn::Add(a, hn::Mul(z.frac, hn::Sub(b, a)));
  };
  const auto e0 = face(x.cell);
  const auto e1 = face(hn::Add(x.cell, one));
  return hn::Add(e0, hn::Mul(x.frac, hn::Sub(e1, e0)));
}

// std::clamp(v, 0, 1) with its comparisons (a NaN stays NaN, whatever the target's Min/Max do).
template <class D>
HWY_INLINE hn::Vec<D> ClampUnitLanes(D d, hn::Vec<D> v) {
  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0);
  return hn::IfThenElse(hn::Lt(v, zero), zero, hn::IfThenElse(hn::Lt(one, v), one, v));
}

// waves::pulse_integral per lane; std::min(a, duty) is duty < a ? duty : a.
template <class D>
HWY_INLINE hn::Vec<D> PulseIntegralLanes(D d, hn::Vec<D> x, hn::Vec<D> duty) {
  const auto whole = hn::Floor(x);
  const auto part = hn::Sub(x, whole);
  (void)d;
  return hn::Add(hn::Mul(whole, duty), hn::IfThenElse(hn::Lt(duty, part), duty, part));
}

// waves::filtered_pulse per lane: every case computed, then chosen in the scalar's order.
template <class D>
HWY_INLINE hn::Vec<D> FilteredPulseLanes(D d, hn::Vec<D> u, double duty_value, hn::Vec<D> w) {
  const auto duty = hn::Set(d, duty_value);
  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0);
  const auto finite = hn::IsFinite(u);
  const auto centre = hn::Sub(u, hn::Floor(u));  // fract(u) where u is finite
  const auto half = hn::Mul(hn::Set(d, 0.5), w);
  const auto difference = hn::Sub(PulseIntegralLanes(d, hn::Add(centre, half), duty),
                                  PulseIntegralLanes(d, hn::Sub(centre, half), duty));
  auto value = ClampUnitLanes(d, hn::Div(difference, w));
  value = hn::IfThenElse(hn::Ge(w, hn::Set(d, waves::kMeanWidth)), duty, value);
  const auto point = hn::IfThenElse(hn::Lt(centre, duty), one, zero);
  value = hn::IfThenElse(hn::Not(hn::Gt(w, hn::Set(d, waves::kPointWidth))), point, value);
  return hn::IfThenElse(finite, value, hn::Set(d, 0.0 < duty_value ? 1.0 : 0.0));
}

// fields::wood along a row: the rotations and the jitter in lanes, then the radius through
// std::hypot per point, then the ring, its width and the filtered pulse in lanes. `scratch`
// holds 3 * nx doubles.
inline void WoodRow(const WoodParams& w, const fields::WoodFrame& frame,
                    const fields::WoodRotation& rotation, const double* xs, double y, double z,
                    const glm::dvec3& box, double* scratch, float* field, std::size_t nx) {
  const hn::ScalableTag<double> dd;
  const hn::Rebind<float, decltype(dd)> df;
  const std::size_t lanes = hn::Lanes(dd);
  const std::size_t whole_vectors = nx / lanes * lanes;
  double* x2s = scratch;
  double* y2s = scratch + nx;
  double* jitters = scratch + 2 * nx;
  const NoiseTables& tables = noise_tables();
  const auto cy = hn::Set(dd, rotation.cos_y), sy = hn::Set(dd, rotation.sin_y);
  const auto minus_sy = hn::Set(dd, -rotation.sin_y);
  const auto cz = hn::Set(dd, frame.cos_tilt_z), sz = hn::Set(dd, frame.sin_tilt_z);
  const auto py = hn::Set(dd, y), pz = hn::Set(dd, z);
  const auto jitter_scale = hn::Set(dd, w.jitter_scale);
  for (std::size_t i = 0; i < whole_vectors; i += lanes) {
    const auto px = hn::LoadU(dd, xs + i);
    const auto x1 = hn::Add(hn::Mul(cy, px), hn::Mul(sy, pz));
    const auto z1 = hn::Add(hn::Mul(minus_sy, px), hn::Mul(cy, pz));
    const auto x2 = hn::Sub(hn::Mul(cz, x1), hn::Mul(sz, py));
    const auto y2 = hn::Add(hn::Mul(sz, x1), hn::Mul(cz, py));
    const auto noise = ValueNoiseLanes(dd, tables, hn::Mul(x2, jitter_scale),
                                       hn::Mul(y2, jitter_scale), hn::Mul(z1, jitter_scale));
    const auto centred = hn::PromoteTo(dd, hn::Sub(noise, hn::Set(df, tables.value_mean)));
    hn::StoreU(x2, dd, x2s + i);
    hn::StoreU(y2, dd, y2s + i);
    hn::StoreU(hn::Mul(hn::Set(dd, w.jitter), centred), dd, jitters + i);
  }
  const bool has_box = box != glm::dvec3(0.0);
  const auto spacing = hn::Set(dd, w.ring_spacing);
  for (std::size_t i = 0; i < whole_vectors; i += lanes) {
    // The library's hypot (no overflow for huge coordinates), as the scalar path calls it.
    HWY_ALIGN double radii[hn::MaxLanes(dd)];
    for (std::size_t k = 0; k < lanes; ++k) radii[k] = std::hypot(x2s[i + k], y2s[i + k]);
    const auto radius = hn::LoadU(dd, radii);
    const auto ring = hn::Add(hn::Div(radius, spacing), hn::LoadU(dd, jitters + i));
    auto ring_width = hn::Zero(dd);
    if (has_box) {
      const auto ux = hn::Div(hn::LoadU(dd, x2s + i), radius);
      const auto uy = hn::Div(hn::LoadU(dd, y2s + i), radius);
      const auto across = hn::Add(hn::Mul(ux, cz), hn::Mul(uy, sz));
      // z1 again (not kept from the first loop: the scratch holds three rows), as it was made.
      const auto z1 = hn::Add(hn::Mul(minus_sy, hn::LoadU(dd, xs + i)), hn::Mul(cy, pz));
      const auto gx = hn::Mul(across, cy);
      const auto gy = hn::Sub(hn::Sub(hn::Mul(uy, cz), hn::Mul(ux, sz)),
                              hn::Mul(hn::Mul(across, hn::Set(dd, w.twist)), z1));
      const auto gz = hn::Mul(across, sy);
      const auto width = hn::Add(hn::Add(hn::Mul(hn::Abs(gx), hn::Set(dd, box.x)),
                                         hn::Mul(hn::Abs(gy), hn::Set(dd, box.y))),
                                 hn::Mul(hn::Abs(gz), hn::Set(dd, box.z)));
      ring_width = hn::IfThenElseZero(hn::Gt(radius, hn::Zero(dd)), hn::Div(width, spacing));
    }
    const auto value = FilteredPulseLanes(dd, ring, w.grain_fraction, ring_width);
    hn::StoreU(hn::DemoteTo(df, value), df, field + i);
  }
  for (std::size_t i = whole_vectors; i < nx; ++i) {
    field[i] = fields::wood(w, frame, rotation, glm::dvec3(xs[i], y, z), box);
  }
}

// ColourRamp::at in lanes. The first key at or above t decides in at(); here the keys are
// visited from the last down, each overriding the lanes it covers, so the lowest such key is
// the one left. Needs at least one key.
template <class DF>
HWY_INLINE void RampAtLanes(DF df, const std::vector<RampKey>& keys, hn::Vec<DF> tv,
                            hn::Vec<DF> (&colour)[3]) {
  for (int c = 0; c < 3; ++c) colour[c] = hn::Set(df, keys.back().colour[c]);
  for (std::size_t k = keys.size() - 1; k >= 1; --k) {
    const RampKey& hi = keys[k];
    const RampKey& lo = keys[k - 1];
    const auto at_hi = hn::Eq(tv, hn::Set(df, hi.position));
    const auto covered = hn::Le(tv, hn::Set(df, hi.position));
    const auto u =
        hn::Div(hn::Sub(tv, hn::Set(df, lo.position)), hn::Set(df, hi.position - lo.position));
    for (int c = 0; c < 3; ++c) {
      const auto mixed =
          hn::Add(hn::Set(df, lo.colour[c]), hn::Mul(u, hn::Set(df, hi.colour[c] - lo.colour[c])));
      const auto value = hn::IfThenElse(at_hi, hn::Set(df, hi.colour[c]), mixed);
      colour[c] = hn::IfThenElse(covered, value, colour[c]);
    }
  }
  // !(t > first key): the first key's colour, NaN included.
  const auto below = hn::Not(hn::Gt(tv, hn::Set(df, keys.front().position)));
  for (int c = 0; c < 3; ++c) {
    colour[c] = hn::IfThenElse(below, hn::Set(df, keys.front().colour[c]), colour[c]);
  }
}

// ColourRamp::RampBox::step_share in lanes: every case computed, then chosen in the scalar's
// order. `half_inverse_width` is 0.5 / width, as the scalar's first product makes it. A NaN
// field's lanes differ from the scalar's here, and the caller gives them at()'s colour.
template <class DF>
HWY_INLINE hn::Vec<DF> RampStepShareLanes(DF df, hn::Vec<DF> t, hn::Vec<DF> spread,
                                          hn::Vec<DF> width, hn::Vec<DF> inverse_width,
                                          hn::Vec<DF> half_inverse_width, float start,
                                          float length_value, float inverse_length_value) {
  const auto length = hn::Set(df, length_value);
  const auto inverse_length = hn::Set(df, inverse_length_value);
  const auto length_narrower = hn::Lt(length, width);
  const auto narrow = hn::IfThenElse(length_narrower, length, width);
  const auto wide = hn::IfThenElse(length_narrower, width, length);
  const auto inverse_wide = hn::IfThenElse(length_narrower, inverse_width, inverse_length);
  const auto whole = hn::Add(narrow, wide);
  const auto e = hn::Add(hn::Sub(t, hn::Set(df, start)), spread);
  const auto inverse_curve = hn::Mul(half_inverse_width, inverse_length);
  const auto one = hn::Set(df, 1.0f);
  const auto rise = hn::Mul(hn::Mul(e, e), inverse_curve);
  const auto rest = hn::Sub(whole, e);
  const auto fall = hn::Sub(one, hn::Mul(hn::Mul(rest, rest), inverse_curve));
  const auto flat = hn::Mul(hn::Sub(e, hn::Mul(hn::Set(df, 0.5f), narrow)), inverse_wide);
  auto share = hn::IfThenElse(hn::Lt(e, narrow), rise, hn::IfThenElse(hn::Gt(e, wide), fall, flat));
  share = hn::IfThenElse(hn::Ge(e, whole), one, share);
  return hn::IfThenZeroElse(hn::Le(e, hn::Zero(df)), share);
}

// ColourRamp::at for n fields, into three colour planes. Needs at least one key.
inline void RampPlanes(const ColourRamp& ramp, const float* t, std::size_t nx, float* red,
                       float* green, float* blue) {
  const hn::ScalableTag<float> df;
  const std::size_t lanes = hn::Lanes(df);
  float* planes[3] = {red, green, blue};
  std::size_t i = 0;
  for (; i + lanes <= nx; i += lanes) {
    hn::Vec<decltype(df)> colour[3];
    RampAtLanes(df, ramp.keys, hn::LoadU(df, t + i), colour);
    for (int c = 0; c < 3; ++c) hn::StoreU(colour[c], df, planes[c] + i);
  }
  for (; i < nx; ++i) {
    const glm::vec3 c = ramp.at(t[i]);
    red[i] = c.r;
    green[i] = c.g;
    blue[i] = c.b;
  }
}

// A ramp's key steps as ColourRamp::average makes them (start, length, 1 / length and the
// colour change), once per grid for the lanes instead of once per point.
struct RampSteps {
  struct Step {
    float start, length, inverse_length;
    glm::vec3 change;
  };
  glm::vec3 first{0.0f}, last{0.0f};
  float last_position = 0.0f;
  std::size_t count = 0;
  Step steps[SpecLimits::kMaxRampKeys];

  explicit RampSteps(const ColourRamp& ramp) {
    const std::vector<RampKey>& keys = ramp.keys;
    if (keys.empty()) return;
    first = keys.front().colour;
    last = keys.back().colour;
    last_position = keys.back().position;
    count = keys.size() - 1;
    for (std::size_t k = 0; k < count; ++k) {
      const float length = keys[k + 1].position - keys[k].position;
      steps[k] = {keys[k].position, length, 1.0f / length, keys[k + 1].colour - keys[k].colour};
    }
  }
};

// ColourRamp::average for n fields and their spreads, into three colour planes: each key
// step adds its colour change times its share, and lanes with no spread (or a NaN field) take
// at()'s colour, as average() does. Needs at least one key.
inline void RampAveragePlanes(const ColourRamp& ramp, const RampSteps& steps, const float* t,
                              const float* spread, std::size_t nx, float* red, float* green,
                              float* blue) {
  const hn::ScalableTag<float> df;
  const std::size_t lanes = hn::Lanes(df);
  float* planes[3] = {red, green, blue};
  std::size_t i = 0;
  for (; i + lanes <= nx; i += lanes) {
    const auto tv = hn::LoadU(df, t + i);
    const auto sv = hn::LoadU(df, spread + i);
    const auto width = hn::Mul(hn::Set(df, 2.0f), sv);
    const auto inverse_width = hn::Div(hn::Set(df, 1.0f), width);
    const auto half_inverse_width = hn::Mul(hn::Set(df, 0.5f), inverse_width);
    hn::Vec<decltype(df)> colour[3];
    for (int c = 0; c < 3; ++c) colour[c] = hn::Set(df, steps.first[c]);
    for (std::size_t k = 0; k < steps.count; ++k) {
      const RampSteps::Step& step = steps.steps[k];
      const auto share = RampStepShareLanes(df, tv, sv, width, inverse_width, half_inverse_width,
                                            step.start, step.length, step.inverse_length);
      for (int c = 0; c < 3; ++c) {
        colour[c] = hn::Add(colour[c], hn::Mul(hn::Set(df, step.change[c]), share));
      }
    }
    // As average(): past the last key its colour, else the sum clamped to [0, 1].
    const auto past_last = hn::Ge(hn::Sub(tv, sv), hn::Set(df, steps.last_position));
    const auto zero = hn::Zero(df);
    const auto one = hn::Set(df, 1.0f);
    for (int c = 0; c < 3; ++c) {
      colour[c] = hn::IfThenElse(hn::Lt(colour[c], zero), zero,
                                 hn::IfThenElse(hn::Lt(one, colour[c]), one, colour[c]));
      colour[c] = hn::IfThenElse(past_last, hn::Set(df, steps.last[c]), colour[c]);
    }
    const auto at_point = hn::Or(hn::Not(hn::Gt(sv, hn::Zero(df))), hn::IsNaN(tv));
    if (!hn::AllFalse(df, at_point)) {
      hn::Vec<decltype(df)> point[3];
      RampAtLanes(df, ramp.keys, tv, point);
      for (int c = 0; c < 3; ++c) colour[c] = hn::IfThenElse(at_point, point[c], colour[c]);
    }
    for (int c = 0; c < 3; ++c) hn::StoreU(colour[c], df, planes[c] + i);
  }
  for (; i < nx; ++i) {
    const glm::vec3 c = ramp.average(t[i], spread[i]);
    red[i] = c.r;
    green[i] = c.g;
    blue[i] = c.b;
  }
}

}  // namespace soltex::pattern_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // SOLTEX_COMMON_GRID_ROW_LANES_INL_H_
