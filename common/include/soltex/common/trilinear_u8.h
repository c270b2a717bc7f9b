#pragma once

#include <cstddef>
#include <cstdint>

#include "soltex/common/sampling_kernels-inl.h"
#include "soltex/common/trilinear_u8_scalar.h"

// Trilinear interpolation of 8-bit samples stored channel-interleaved (all channels of one
// sample next to each other, x fastest, then y, then z). trilinear_u8() is the per-sample
// form, compiled for the build's static Highway target (SIMD only where the compiler flags
// allow it, scalar in the generic build); sampling_kernels.h has the batch form, dispatched
// at run time. The brick cache samples through them, and so does anything else holding
// such a lattice (the dense-array baseline of tests/bench/sampler_bench.cpp), so a comparison
// between them measures the lookup, not two different kernels.
namespace soltex {

// `s` points at the first channel of the corner sample (x, y, z); its neighbours are at
// +Channels (x + 1), +y_stride (y + 1) and +z_stride (z + 1) bytes. f* are the fractions in
// [0, 1] along each axis. Writes Channels values in [0, 1] (sample / 255); `out` must hold
// max(Channels, 4) floats: the 3-channel SIMD path writes a fourth, 0 (the scalar path
// leaves it alone).
// HWY_ATTR: compiled with the static target's instruction set, as the kernel it inlines is.
// Where the build's flags already imply it (a native build), callers inline this too; where
// they do not (on ARM, NEON's attribute adds the crypto extension), it is called.
template <int Channels>
HWY_ATTR inline void trilinear_u8(const uint8_t* s, std::ptrdiff_t y_stride,
                                  std::ptrdiff_t z_stride, float fx, float fy, float fz,
                                  float* out) {
  // The emulated 128-bit target is slower than the scalar code; every real SIMD target is
  // faster. Both give the same bits.
#if HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR
  if constexpr (Channels == 3 || Channels == 4) {
    HWY_NAMESPACE::sampling_kernels::trilinear<Channels>(s, y_stride, z_stride, fx, fy, fz, out);
    return;
  }
#endif
  trilinear_detail::scalar<Channels>(s, y_stride, z_stride, fx, fy, fz, out);
}

}  // namespace soltex
