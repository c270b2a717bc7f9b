#pragma once

#include <cstddef>
#include <cstdint>

#if defined(__SSE4_1__)
#include <immintrin.h>
#endif

// Trilinear interpolation of 8-bit samples stored channel-interleaved (all channels of one
// sample next to each other, x fastest, then y, then z). The brick cache samples through it,
// and so does anything else holding such a lattice (the dense-array baseline of
// tests/bench/sampler_bench.cpp), so a comparison between them measures the lookup, not two
// different kernels.
namespace soltex {

// Bytes a caller must keep readable after the last sample: the 3- and 4-channel paths load
// the two x-neighbours of a row with one 8-byte load.
inline constexpr std::size_t kTrilinearLoadPadding = 8;

namespace trilinear_detail {

inline float lerp(float a, float b, float t) {
  return a + t * (b - a);
}

template <int Channels>
inline void scalar(const uint8_t* s, std::ptrdiff_t y_stride, std::ptrdiff_t z_stride, float fx,
                   float fy, float fz, float* out) {
  const uint8_t* r00 = s;
  const uint8_t* r10 = s + y_stride;
  const uint8_t* r01 = s + z_stride;
  const uint8_t* r11 = s + y_stride + z_stride;
  for (int c = 0; c < Channels; ++c) {
    const float x00 = lerp(r00[c], r00[Channels + c], fx);
    const float x10 = lerp(r10[c], r10[Channels + c], fx);
    const float x01 = lerp(r01[c], r01[Channels + c], fx);
    const float x11 = lerp(r11[c], r11[Channels + c], fx);
    const float y0 = lerp(x00, x10, fy);
    const float y1 = lerp(x01, x11, fy);
    out[c] = lerp(y0, y1, fz) * (1.0f / 255.0f);
  }
}

#if defined(__SSE4_1__)
// One row of two x-neighbours, widened to floats: lanes [c0 of x, ..] and [c0 of x+1, ..].
// For 3 channels the 8-byte load also reads 2 bytes of the next sample (or the padding);
// the shuffle drops them, so lane 3 is 0.
template <int Channels>
inline void row_pair(const uint8_t* row, __m128& left, __m128& right) {
  static_assert(Channels == 3 || Channels == 4);
  __m128i bytes = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(row));
  if constexpr (Channels == 3) {
    bytes = _mm_shuffle_epi8(
        bytes, _mm_setr_epi8(0, 1, 2, -1, 3, 4, 5, -1, -1, -1, -1, -1, -1, -1, -1, -1));
  }
  left = _mm_cvtepi32_ps(_mm_cvtepu8_epi32(bytes));
  right = _mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_srli_si128(bytes, 4)));
}

inline __m128 lerp4(__m128 a, __m128 b, __m128 t) {
  return _mm_add_ps(a, _mm_mul_ps(t, _mm_sub_ps(b, a)));
}

// The same operations in the same order as scalar(), four channels at once: results are
// bit-identical to the scalar path.
template <int Channels>
inline void simd(const uint8_t* s, std::ptrdiff_t y_stride, std::ptrdiff_t z_stride, float fx,
                 float fy, float fz, float* out) {
  __m128 l00, r00, l10, r10, l01, r01, l11, r11;
  row_pair<Channels>(s, l00, r00);
  row_pair<Channels>(s + y_stride, l10, r10);
  row_pair<Channels>(s + z_stride, l01, r01);
  row_pair<Channels>(s + y_stride + z_stride, l11, r11);
  const __m128 tx = _mm_set1_ps(fx);
  const __m128 ty = _mm_set1_ps(fy);
  const __m128 x00 = lerp4(l00, r00, tx);
  const __m128 x10 = lerp4(l10, r10, tx);
  const __m128 x01 = lerp4(l01, r01, tx);
  const __m128 x11 = lerp4(l11, r11, tx);
  const __m128 y0 = lerp4(x00, x10, ty);
  const __m128 y1 = lerp4(x01, x11, ty);
  // One 16-byte store, also for 3 channels (lane 3 is 0 then): a caller that reads the
  // values back as one vector (a returned struct) gets them forwarded from this store;
  // three narrower stores would stall that load.
  _mm_storeu_ps(out, _mm_mul_ps(lerp4(y0, y1, _mm_set1_ps(fz)), _mm_set1_ps(1.0f / 255.0f)));
}
#endif

#if defined(__AVX2__)
// Two rows (y and y + 1 at one z) at once, widened to floats: `left` holds the x samples of
// both rows ([row y | row y + 1], four lanes each), `right` the x + 1 samples.
template <int Channels>
inline void two_row_pairs(const uint8_t* row, std::ptrdiff_t y_stride, __m256& left,
                          __m256& right) {
  static_assert(Channels == 3 || Channels == 4);
  // Bytes 0..7: row y's pair; 8..15: row y + 1's pair (8-byte loads, as in row_pair).
  const __m128i bytes = _mm_castpd_si128(
      _mm_loadh_pd(_mm_castsi128_pd(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(row))),
                   reinterpret_cast<const double*>(row + y_stride)));
  // Regrouped as [x of row y, x of row y + 1, x + 1 of row y, x + 1 of row y + 1].
  const __m128i grouped =
      Channels == 3
          ? _mm_shuffle_epi8(bytes,
                             _mm_setr_epi8(0, 1, 2, -1, 8, 9, 10, -1, 3, 4, 5, -1, 11, 12, 13, -1))
          : _mm_shuffle_epi8(bytes,
                             _mm_setr_epi8(0, 1, 2, 3, 8, 9, 10, 11, 4, 5, 6, 7, 12, 13, 14, 15));
  left = _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(grouped));
  right = _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_srli_si128(grouped, 8)));
}

inline __m256 lerp8(__m256 a, __m256 b, __m256 t) {
  return _mm256_add_ps(a, _mm256_mul_ps(t, _mm256_sub_ps(b, a)));
}

// simd() with two rows per 8-lane operation: the same operations on the same lanes in the
// same order, so bit-identical too, in about half the instructions.
template <int Channels>
inline void simd2(const uint8_t* s, std::ptrdiff_t y_stride, std::ptrdiff_t z_stride, float fx,
                  float fy, float fz, float* out) {
  __m256 left0, right0, left1, right1;
  two_row_pairs<Channels>(s, y_stride, left0, right0);             // z
  two_row_pairs<Channels>(s + z_stride, y_stride, left1, right1);  // z + 1
  const __m256 tx = _mm256_set1_ps(fx);
  const __m256 x0 = lerp8(left0, right0, tx);                  // [x00 | x10]
  const __m256 x1 = lerp8(left1, right1, tx);                  // [x01 | x11]
  const __m256 y_low = _mm256_permute2f128_ps(x0, x1, 0x20);   // [x00 | x01]
  const __m256 y_high = _mm256_permute2f128_ps(x0, x1, 0x31);  // [x10 | x11]
  const __m256 y = lerp8(y_low, y_high, _mm256_set1_ps(fy));   // [y0 | y1]
  const __m128 v = lerp4(_mm256_castps256_ps128(y), _mm256_extractf128_ps(y, 1), _mm_set1_ps(fz));
  _mm_storeu_ps(out, _mm_mul_ps(v, _mm_set1_ps(1.0f / 255.0f)));  // one store: see simd()
}
#endif

}  // namespace trilinear_detail

// `s` points at the first channel of the corner sample (x, y, z); its neighbours are at
// +Channels (x + 1), +y_stride (y + 1) and +z_stride (z + 1) bytes. f* are the fractions in
// [0, 1] along each axis. Writes Channels values in [0, 1] (sample / 255); `out` must hold
// max(Channels, 4) floats (the 3-channel path writes a fourth, unspecified).
template <int Channels>
inline void trilinear_u8(const uint8_t* s, std::ptrdiff_t y_stride, std::ptrdiff_t z_stride,
                         float fx, float fy, float fz, float* out) {
#if defined(__AVX2__)
  if constexpr (Channels == 3 || Channels == 4) {
    trilinear_detail::simd2<Channels>(s, y_stride, z_stride, fx, fy, fz, out);
    return;
  }
#elif defined(__SSE4_1__)
  if constexpr (Channels == 3 || Channels == 4) {
    trilinear_detail::simd<Channels>(s, y_stride, z_stride, fx, fy, fz, out);
    return;
  }
#endif
  trilinear_detail::scalar<Channels>(s, y_stride, z_stride, fx, fy, fz, out);
}

}  // namespace soltex
