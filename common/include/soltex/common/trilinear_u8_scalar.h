#pragma once

#include <cstddef>
#include <cstdint>

// The scalar trilinear kernel over channel-interleaved 8-bit samples (see trilinear_u8.h): the
// reference every SIMD target of the kernel reproduces bit for bit. Free of Highway, so the
// runtime-dispatched unit (sampling_kernels.cpp) can include it before hwy/foreach_target.h.
namespace soltex {

// Bytes a caller must keep readable after the last sample: the 3- and 4-channel paths load
// each x-neighbour of a row with one 4-byte load, up to 8 bytes from the row's start.
inline constexpr std::size_t kTrilinearLoadPadding = 8;

namespace trilinear_detail {

// Every byte as a float, exactly (static_cast<float>(b)). Without SSE4 or AVX, an 8-bit to
// float conversion is a two-uop cvtsi2ss per channel and corner (24 per RGB lookup), with a
// false dependency on its destination; a load from this 1 KiB table is one uop and gives the
// same bits.
struct ByteFloats {
  float value[256];
  constexpr ByteFloats() : value{} {
    for (int b = 0; b < 256; ++b) value[b] = static_cast<float>(b);
  }
};
inline constexpr ByteFloats kByteFloats{};

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
  const float* f = kByteFloats.value;
  for (int c = 0; c < Channels; ++c) {
    const float x00 = lerp(f[r00[c]], f[r00[Channels + c]], fx);
    const float x10 = lerp(f[r10[c]], f[r10[Channels + c]], fx);
    const float x01 = lerp(f[r01[c]], f[r01[Channels + c]], fx);
    const float x11 = lerp(f[r11[c]], f[r11[Channels + c]], fx);
    const float y0 = lerp(x00, x10, fy);
    const float y1 = lerp(x01, x11, fy);
    out[c] = lerp(y0, y1, fz) * (1.0f / 255.0f);
  }
}

}  // namespace trilinear_detail

}  // namespace soltex
