// The SIMD kernels of cached sampling, written once with Highway and compiled per target.
//
// Included in two ways (Highway's "-inl.h" convention, hence the toggled guard instead of
// #pragma once):
//   - by trilinear_u8.h and sample_split.h, once, for the build's static target: the
//     per-sample inline path, as fast as the compiler flags allow;
//   - by common/src/sampling_kernels.cpp under hwy/foreach_target.h, once per target: the
//     batch entry points, chosen at run time (HWY_DYNAMIC_DISPATCH) once per batch.
//
// Bit-exactness: every lane performs the scalar path's IEEE operations in the scalar path's
// order (lerp is a + t * (b - a), a Mul then an Add, never a fused MulAdd; the build has
// -ffp-contract=off), so every target gives the scalar bits.

#if defined(SOLTEX_COMMON_SAMPLING_KERNELS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SOLTEX_COMMON_SAMPLING_KERNELS_INL_H_
#undef SOLTEX_COMMON_SAMPLING_KERNELS_INL_H_
#else
#define SOLTEX_COMMON_SAMPLING_KERNELS_INL_H_
#endif

#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace soltex::HWY_NAMESPACE {
namespace sampling_kernels {

namespace hn = hwy::HWY_NAMESPACE;

template <class V>
HWY_INLINE V lerp(V a, V b, V t) {
  return hn::Add(a, hn::Mul(t, hn::Sub(b, a)));
}

#if HWY_TARGET != HWY_SCALAR  // vectors of four floats exist on every target but this one
// Four bytes as four float lanes.
HWY_INLINE hn::Vec<hn::FixedTag<float, 4>> widen4(uint32_t bytes) {
  const hn::FixedTag<int32_t, 4> di;
  const hn::Rebind<uint8_t, decltype(di)> d8;
  const hn::Repartition<uint32_t, decltype(d8)> d32x1;
  const auto v = hn::BitCast(d8, hn::Set(d32x1, bytes));
  return hn::ConvertTo(hn::FixedTag<float, 4>(), hn::PromoteTo(di, v));
}

inline uint32_t load4(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// The last store: lanes scaled to [0, 1]; a 3-channel sample's fourth lane is 0 (it held the
// next sample's first channel), so every target writes the same four floats.
template <int Channels>
HWY_INLINE void store_scaled(hn::Vec<hn::FixedTag<float, 4>> v, float* out) {
  const hn::FixedTag<float, 4> d;
  v = hn::Mul(v, hn::Set(d, 1.0f / 255.0f));
  if constexpr (Channels == 3) v = hn::IfThenElseZero(hn::FirstN(d, 3), v);
  hn::StoreU(v, d, out);
}

// Channels 3 or 4: `s` is the corner sample; writes 4 floats (see store_scaled).
// With 256-bit vectors, two rows (y and y + 1 at one z) share each operation.
template <int Channels>
HWY_INLINE void trilinear(const uint8_t* s, std::ptrdiff_t y_stride, std::ptrdiff_t z_stride,
                          float fx, float fy, float fz, float* out) {
  static_assert(Channels == 3 || Channels == 4);
  const hn::FixedTag<float, 4> d4;
#if HWY_MAX_BYTES >= 32
  const hn::FixedTag<float, 8> d8;
  const hn::Rebind<int32_t, decltype(d8)> di8;
  const hn::Rebind<uint8_t, decltype(di8)> du8;
  const hn::Repartition<uint64_t, decltype(du8)> d64x1;
  // [x of row y | x of row y + 1] and [x + 1 of row y | x + 1 of row y + 1], as floats.
  const auto rows = [&](const uint8_t* row, auto& left, auto& right) {
    const uint64_t l = load4(row) | uint64_t{load4(row + y_stride)} << 32;
    const uint64_t r = load4(row + Channels) | uint64_t{load4(row + y_stride + Channels)} << 32;
    left = hn::ConvertTo(d8, hn::PromoteTo(di8, hn::BitCast(du8, hn::Set(d64x1, l))));
    right = hn::ConvertTo(d8, hn::PromoteTo(di8, hn::BitCast(du8, hn::Set(d64x1, r))));
  };
  hn::Vec<decltype(d8)> left0, right0, left1, right1;
  rows(s, left0, right0);             // z
  rows(s + z_stride, left1, right1);  // z + 1
  const auto tx = hn::Set(d8, fx);
  const auto x0 = lerp(left0, right0, tx);               // [x00 | x10]
  const auto x1 = lerp(left1, right1, tx);               // [x01 | x11]
  const auto y_low = hn::ConcatLowerLower(d8, x1, x0);   // [x00 | x01]
  const auto y_high = hn::ConcatUpperUpper(d8, x1, x0);  // [x10 | x11]
  const auto y = lerp(y_low, y_high, hn::Set(d8, fy));   // [y0 | y1]
  store_scaled<Channels>(lerp(hn::LowerHalf(d4, y), hn::UpperHalf(d4, y), hn::Set(d4, fz)), out);
#else
  const auto tx = hn::Set(d4, fx);
  const auto row = [&](const uint8_t* r) {
    return lerp(widen4(load4(r)), widen4(load4(r + Channels)), tx);
  };
  const auto x00 = row(s);
  const auto x10 = row(s + y_stride);
  const auto x01 = row(s + z_stride);
  const auto x11 = row(s + y_stride + z_stride);
  const auto ty = hn::Set(d4, fy);
  const auto y0 = lerp(x00, x10, ty);
  const auto y1 = lerp(x01, x11, ty);
  store_scaled<Channels>(lerp(y0, y1, hn::Set(d4, fz)), out);
#endif
}
#endif

// The cell split of sample_split.h, lane by lane (lanes are points, or the axes of one point):
//   u = clamp((p - origin) / spacing * scale, 0, cells), NaN to +0
//   cell = min(trunc(u), cells - 1), frac = float(u - cell).
// Stores Lanes(d) cells and fractions.
template <class D, class V = hn::Vec<D>>
HWY_INLINE void split_lanes(D d, V p, V origin, V spacing, V scale, V cells, int32_t* cell_out,
                            float* frac_out) {
  const hn::Rebind<int32_t, D> di;
  const hn::Rebind<float, D> df;
  const V u = hn::Mul(hn::Div(hn::Sub(p, origin), spacing), scale);
  // Gt is false for NaN and for -0: both become +0, as in the scalar u > 0 ? ... : 0.
  const V zero = hn::Zero(d);
  const V clamped = hn::IfThenElse(hn::Gt(u, zero), hn::Min(u, cells), zero);
  // clamped is in [0, cells]: the truncating conversion is floor; cells - 1 is exact.
  const auto cell =
      hn::Min(hn::DemoteTo(di, clamped), hn::DemoteTo(di, hn::Sub(cells, hn::Set(d, 1.0))));
  hn::StoreU(cell, di, cell_out);
  hn::StoreU(hn::DemoteTo(df, hn::Sub(clamped, hn::PromoteTo(d, cell))), df, frac_out);
}

}  // namespace sampling_kernels
}  // namespace soltex::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
