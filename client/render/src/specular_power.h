#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>

// x^exponent for the Blinn-Phong highlight: x = n.h in (0, 1], exponent = shininess in
// [1, 10000]. Written as plain arithmetic, without calls or branches, so that the batched
// lighting loop vectorises; the scalar and the batched lighting both call it and agree bit
// for bit. Relative error against std::pow, wherever the result is a normal float: below
// 2e-5 for shininess 1 to 10000 (std::exp2(s * std::log2(x)) in float, which it replaces, is
// below 7e-6; an 8-bit highlight cannot tell).
namespace soltex::render_internal {

// log2(x) for x > 0: x = m * 2^e with m in [sqrt(1/2), sqrt(2)), then the series
// ln m = 2 (t + t^3/3 + t^5/5 + ...), t = (m - 1) / (m + 1), |t| <= 0.172, where five terms
// leave an error below float's rounding. x below the smallest normal float counts as it.
inline float log2_of_positive(float x) {
  constexpr float kMinNormal = std::numeric_limits<float>::min();
  const float normal = x < kMinNormal ? kMinNormal : x;
  const auto bits = std::bit_cast<uint32_t>(normal);
  const int32_t exponent = static_cast<int32_t>(bits >> 23) - 127;
  const float mantissa = std::bit_cast<float>((bits & 0x007fffffu) | 0x3f800000u);  // [1, 2)
  const bool upper = mantissa > 1.41421356f;
  const float m = upper ? mantissa * 0.5f : mantissa;
  const float e = static_cast<float>(exponent + (upper ? 1 : 0));
  const float t = (m - 1.0f) / (m + 1.0f);
  const float t2 = t * t;
  const float ln_m =
      t *
      (2.0f + t2 * (2.0f / 3.0f + t2 * (2.0f / 5.0f + t2 * (2.0f / 7.0f + t2 * (2.0f / 9.0f)))));
  return e + ln_m * 1.44269504f;  // 1 / ln 2
}

// 2^y: y = n + f with n an integer and f in [0, 1), 2^f = e^(f ln 2) by its Taylor polynomial
// to degree 8 (remainder below 1.1e-7 for f ln 2 < 0.694), exact at f = 0, and n added to the
// float's exponent. Below -126 (where 2^y is no longer a normal float) the result is 0; y is at
// most 0 here, as x <= 1, but a rounding excess up to 127 is fine.
inline float exp2_of(float y) {
  // max/min, not a chain of selects: those kept the loop scalar. NaN (a lane the caller
  // discards) becomes -126, as a float-to-int conversion of NaN is undefined.
  const float clamped = std::min(127.0f, std::max(-126.0f, y));
  const auto truncated = static_cast<int32_t>(clamped);  // towards zero
  const int32_t n = truncated - static_cast<int32_t>(static_cast<float>(truncated) > clamped);
  const float u = (clamped - static_cast<float>(n)) * 0.693147181f;
  const float p =
      1.0f + u * (1.0f + u * (1.0f / 2.0f +
                              u * (1.0f / 6.0f +
                                   u * (1.0f / 24.0f +
                                        u * (1.0f / 120.0f +
                                             u * (1.0f / 720.0f + u * (1.0f / 5040.0f +
                                                                       u * (1.0f / 40320.0f))))))));
  const float scaled = std::bit_cast<float>(
      static_cast<uint32_t>(static_cast<int32_t>(std::bit_cast<uint32_t>(p)) + n * (1 << 23)));
  // A product, not a select (that one kept the loop scalar): exact, as scaled is finite.
  return scaled * static_cast<float>(!(y < -126.0f));
}

inline float specular_power(float x, float exponent) {
  return exp2_of(exponent * log2_of_positive(x));
}

}  // namespace soltex::render_internal
