// The vector building blocks of gradient noise, and fractal_sum at one point in the gradient
// basis with one octave per lane, written once with Highway and compiled per target.
//
// Highway's "-inl.h" convention (a toggled guard instead of #pragma once): included under
// hwy/foreach_target.h by noise_kernels.cpp (the row kernels and the single-point entry
// points) and by pattern_kernels.cpp (whole textures per batch, which call the single-point
// sum of their own target without a dispatch per point).
//
// Every lane executes the scalar path's operations in its order, so every target gives the
// bits of gradient_noise.h and fractal_sum.

#if defined(SOLTEX_COMMON_FRACTAL_POINT_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SOLTEX_COMMON_FRACTAL_POINT_INL_H_
#undef SOLTEX_COMMON_FRACTAL_POINT_INL_H_
#else
#define SOLTEX_COMMON_FRACTAL_POINT_INL_H_
#endif

#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>

#include "noise_kernels.h"
#include "soltex/common/fractal.h"
#include "soltex/common/gradient_noise.h"
#include "soltex/common/noise_tables.h"
#include "value_fractal_sum.h"

HWY_BEFORE_NAMESPACE();
namespace soltex::noise_kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Mul then Add, never fused: the build forbids contraction so that every target and the
// scalar path round alike.
template <class V>
HWY_INLINE V Lerp(V a, V b, V t) {
  return hn::Add(a, hn::Mul(t, hn::Sub(b, a)));
}

// fade(t) = t * t * t * (t * (t * 6 - 15) + 10), in gradient_noise.h's order.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V Fade(D df, V t) {
  const V poly = hn::Add(hn::Mul(t, hn::Sub(hn::Mul(t, hn::Set(df, 6.0f)), hn::Set(df, 15.0f))),
                         hn::Set(df, 10.0f));
  return hn::Mul(hn::Mul(hn::Mul(t, t), t), poly);
}

// detail::gradient_component for a vector of hashes already shifted left by one (2 * h).
template <class D>
HWY_INLINE hn::Vec<D> GradientComponent(D df, uint32_t packed,
                                        hn::Vec<hn::RebindToSigned<D>> twice_h) {
  const hn::RebindToSigned<D> di;
  const hn::RebindToUnsigned<D> du;
  const auto bits =
      hn::And(hn::Shr(hn::Set(du, packed), hn::BitCast(du, twice_h)), hn::Set(du, 3u));
  return hn::ConvertTo(df, hn::Sub(hn::BitCast(di, bits), hn::Set(di, 1)));
}

// The y-z quantities of gradient_row, per lane.
template <class D>
struct GradientRowVec {
  hn::Vec<D> fy0, fy1, fz0, fz1;  // fractions and fractions - 1
  hn::Vec<D> v, w;                // fade(fy), fade(fz)
};

// gradient_cell_edges' face from its four corner hashes perm[x + h<dy><dz>] (unmasked):
// value(fx) = offset + slope * (fx - dx).
template <class D, class VI = hn::Vec<hn::RebindToSigned<D>>>
HWY_INLINE void GradientFace(D df, const GradientRowVec<D>& row, VI p00, VI p10, VI p01, VI p11,
                             hn::Vec<D>& slope, hn::Vec<D>& offset) {
  const hn::RebindToSigned<D> di;
  using V = hn::Vec<D>;
  // (hash & 15) * 2: the shift GradientComponent needs.
  const auto twice = [&](VI hash) {
    const VI masked = hn::And(hash, hn::Set(di, 15));
    return hn::Add(masked, masked);
  };
  const VI h00 = twice(p00), h10 = twice(p10), h01 = twice(p01), h11 = twice(p11);
  const auto gx = [&](VI h2) { return GradientComponent(df, detail::kPackedX, h2); };
  const auto dot = [&](VI h2, V fy, V fz) {
    return hn::Add(hn::Mul(GradientComponent(df, detail::kPackedY, h2), fy),
                   hn::Mul(GradientComponent(df, detail::kPackedZ, h2), fz));
  };
  const V s0 = Lerp(gx(h00), gx(h10), row.v);
  const V s1 = Lerp(gx(h01), gx(h11), row.v);
  const V o0 = Lerp(dot(h00, row.fy0, row.fz0), dot(h10, row.fy1, row.fz0), row.v);
  const V o1 = Lerp(dot(h01, row.fy0, row.fz1), dot(h11, row.fy1, row.fz1), row.v);
  slope = Lerp(s0, s1, row.w);
  offset = Lerp(o0, o1, row.w);
}

// ---- One point, one octave per lane ------------------------------------------------------
//
// fractal_sum's octaves are independent noise evaluations at one point: lanes of doubles carry
// the octaves' lattice coordinates, and lanes of floats (as many) their noise.

template <class D64>
struct SplitVec {
  hn::Vec<hn::Rebind<int32_t, D64>> cell;
  hn::Vec<hn::Rebind<float, D64>> frac;
};

// split_lattice per lane: the same cell and fraction. floor(t) mod 256 comes from
// whole - 256 * floor(whole / 256), exact in double, so no 64-bit integer conversion is needed.
template <class D64>
HWY_INLINE SplitVec<D64> SplitLattice(D64 dd, hn::Vec<D64> t) {
  t = hn::IfThenElseZero(hn::Lt(hn::Abs(t), hn::Set(dd, 0x1p62)), t);
  const auto whole = hn::Floor(t);
  const auto high = hn::Floor(hn::Mul(whole, hn::Set(dd, 1.0 / 256.0)));
  const auto wrapped = hn::Sub(whole, hn::Mul(hn::Set(dd, 256.0), high));
  return {hn::DemoteTo(hn::Rebind<int32_t, D64>(), wrapped),
          hn::DemoteTo(hn::Rebind<float, D64>(), hn::Sub(t, whole))};
}

// Gradient noise at lattice points (tx, ty, tz), one per lane: gradient_noise's operations.
template <class D64>
HWY_INLINE hn::Vec<hn::Rebind<float, D64>> GradientNoise(D64 dd, hn::Vec<D64> tx, hn::Vec<D64> ty,
                                                         hn::Vec<D64> tz) {
  using DF32 = hn::Rebind<float, D64>;
  using DI32 = hn::Rebind<int32_t, D64>;
  using VI = hn::Vec<DI32>;
  const DF32 df;
  const DI32 di;
  const int32_t* HWY_RESTRICT perm = noise_tables().perm.data();
  const SplitVec<D64> x = SplitLattice(dd, tx), y = SplitLattice(dd, ty), z = SplitLattice(dd, tz);
  const auto p = [&](VI cell, VI h) { return hn::GatherIndex(di, perm, hn::Add(cell, h)); };
  const VI one = hn::Set(di, 1);
  // row_hashes
  const VI pz0 = hn::GatherIndex(di, perm, z.cell), pz1 = p(z.cell, one);
  const VI y1 = hn::Add(y.cell, one);
  const VI h00 = p(y.cell, pz0), h10 = p(y1, pz0), h01 = p(y.cell, pz1), h11 = p(y1, pz1);
  const auto one_f = hn::Set(df, 1.0f);
  const GradientRowVec<DF32> row{y.frac,           hn::Sub(y.frac, one_f),
                                 z.frac,           hn::Sub(z.frac, one_f),
                                 Fade(df, y.frac), Fade(df, z.frac)};
  const VI x1 = hn::Add(x.cell, one);
  hn::Vec<DF32> slope0, offset0, slope1, offset1;
  GradientFace(df, row, p(x.cell, h00), p(x.cell, h10), p(x.cell, h01), p(x.cell, h11), slope0,
               offset0);
  GradientFace(df, row, p(x1, h00), p(x1, h10), p(x1, h01), p(x1, h11), slope1, offset1);
  // gradient_cell_finish
  const auto a0 = hn::Add(offset0, hn::Mul(slope0, x.frac));
  const auto a1 = hn::Add(offset1, hn::Mul(slope1, hn::Sub(x.frac, one_f)));
  return Lerp(a0, a1, Fade(df, x.frac));
}

// fractal_sum in the gradient basis: the octave terms in lanes, then summed in octave order as
// the definition does.
inline float GradientFractalSum(const OctavePlan& plan, const glm::dvec3& point) {
  using D64 = hn::ScalableTag<double>;
  const D64 dd;
  const hn::Rebind<float, D64> df;
  static_assert(OctavePlan::kLaneRoom >= SpecLimits::kMaxOctaveCount + kPad);
  HWY_ALIGN float term[OctavePlan::kLaneRoom];
  const std::size_t count = static_cast<std::size_t>(plan.count);
  for (std::size_t k = 0; k < count; k += hn::Lanes(dd)) {
    const auto f = hn::Load(dd, plan.lane_frequency.data() + k);
    auto noise = GradientNoise(dd, hn::Mul(hn::Set(dd, point.x), f),
                               hn::Mul(hn::Set(dd, point.y), f), hn::Mul(hn::Set(dd, point.z), f));
    if (plan.absolute) noise = hn::Abs(noise);
    const auto w = hn::Load(df, plan.lane_noise_weight.data() + k);
    const auto m = hn::Load(df, plan.lane_mean_term.data() + k);
    // octave_term; a faded-out octave adds its mean alone, as fractal_sum's definition says.
    const auto t = hn::IfThenElse(hn::Eq(w, hn::Zero(df)), m, hn::Add(hn::Mul(w, noise), m));
    hn::Store(t, df, term + k);
  }
  float sum = 0.0f;
  for (std::size_t k = 0; k < count; ++k) sum += term[k];
  return sum;
}

// fractal_sum at one point for this target: the gradient basis one octave per lane, the value
// basis octave by octave (its corner lookups are two dependent table reads per lane, measured
// slower as gathers than as scalar loads), compiled for this target's instructions.
inline float FractalSumAt(const OctavePlan& plan, const glm::dvec3& point) {
  if (plan.basis == NoiseBasis::gradient) return GradientFractalSum(plan, point);
  return plan.absolute ? detail::value_fractal_sum<true>(plan, point)
                       : detail::value_fractal_sum<false>(plan, point);
}

}  // namespace soltex::noise_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
