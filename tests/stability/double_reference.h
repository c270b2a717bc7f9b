#pragma once

#include <algorithm>
#include <cmath>
#include <glm/vec3.hpp>
#include <numbers>

#include "soltex/common/noise_tables.h"
#include "soltex/common/texture_spec.h"

// The texture functions written out again in double precision (long double where a product
// must stay exact), from the same tables, by a different route than the library: the cell
// comes from fmod rather than a floor of a quotient, corners are hashed with explicit masks,
// and the trilinear interpolation runs x first. The stability tests compare the library's
// float results against these.
namespace soltex::reference {

struct Split {
  int cell;     // floor(t) mod 256
  double frac;  // t - floor(t), exact
};

inline Split split(double t) {
  if (!std::isfinite(t)) t = 0.0;  // the documented treatment of non-finite coordinates
  const double whole = std::floor(t);
  double wrapped = std::fmod(whole, 256.0);  // exact; takes the sign of `whole`
  if (wrapped < 0.0) wrapped += 256.0;
  return {static_cast<int>(wrapped), t - whole};
}

inline int hash(int ix, int iy, int iz) {
  const auto& p = noise_tables().perm;
  return p[static_cast<std::size_t>(
      (ix + p[static_cast<std::size_t>((iy + p[static_cast<std::size_t>(iz & 255)]) & 255)]) &
      255)];
}

inline double lerp(double a, double b, double t) {
  return a + t * (b - a);
}

inline double value_noise(const glm::dvec3& t) {
  const Split x = split(t.x), y = split(t.y), z = split(t.z);
  const auto& v = noise_tables().value;
  const auto corner = [&](int dx, int dy, int dz) {
    return static_cast<double>(v[static_cast<std::size_t>(
        hash((x.cell + dx) & 255, (y.cell + dy) & 255, (z.cell + dz) & 255))]);
  };
  const double x00 = lerp(corner(0, 0, 0), corner(1, 0, 0), x.frac);
  const double x10 = lerp(corner(0, 1, 0), corner(1, 1, 0), x.frac);
  const double x01 = lerp(corner(0, 0, 1), corner(1, 0, 1), x.frac);
  const double x11 = lerp(corner(0, 1, 1), corner(1, 1, 1), x.frac);
  return lerp(lerp(x00, x10, y.frac), lerp(x01, x11, y.frac), z.frac);
}

// Improved noise with the gradient list of Perlin's 2002 paper: the twelve cube edges, then
// (1,1,0), (-1,1,0), (0,-1,1), (0,-1,-1).
inline double gradient_noise(const glm::dvec3& t) {
  static constexpr double kGradient[16][3] = {{1, 1, 0}, {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0},
                                              {1, 0, 1}, {-1, 0, 1}, {1, 0, -1}, {-1, 0, -1},
                                              {0, 1, 1}, {0, -1, 1}, {0, 1, -1}, {0, -1, -1},
                                              {1, 1, 0}, {-1, 1, 0}, {0, -1, 1}, {0, -1, -1}};
  const Split x = split(t.x), y = split(t.y), z = split(t.z);
  const auto dot = [&](int dx, int dy, int dz) {
    const double* g =
        kGradient[hash((x.cell + dx) & 255, (y.cell + dy) & 255, (z.cell + dz) & 255) & 15];
    return g[0] * (x.frac - dx) + g[1] * (y.frac - dy) + g[2] * (z.frac - dz);
  };
  const auto fade = [](double u) { return u * u * u * (u * (u * 6.0 - 15.0) + 10.0); };
  const double u = fade(x.frac), v = fade(y.frac), w = fade(z.frac);
  const double x00 = lerp(dot(0, 0, 0), dot(1, 0, 0), u);
  const double x10 = lerp(dot(0, 1, 0), dot(1, 1, 0), u);
  const double x01 = lerp(dot(0, 0, 1), dot(1, 0, 1), u);
  const double x11 = lerp(dot(0, 1, 1), dot(1, 1, 1), u);
  return lerp(lerp(x00, x10, v), lerp(x01, x11, v), w);
}

inline double table_mean() {
  double sum = 0.0;
  for (float v : noise_tables().value) sum += v;
  return sum / 256.0;
}

// The band-limited sum of docs/TEXTURES.md: octave k has frequency scale * 2^k, weight 2^-k,
// visibility alpha_k = 1 - smoothstep(0.25, 0.5, f_k * w), and its mean where it fades.
struct FractalSum {
  double raw;           // sum of the octaves
  double total_weight;  // sum of 2^-k
};

inline FractalSum fractal(const FractalParams& f, double filter_width, const glm::dvec3& p) {
  const double mean = f.basis == NoiseBasis::value ? table_mean()
                      : f.signed_octaves           ? 0.0
                                                   : 0.2204;  // kGradientAbsMean
  FractalSum sum{0.0, 0.0};
  for (int k = f.octave_min; k <= f.octave_max; ++k) {
    const double frequency = std::ldexp(f.scale, k);
    const double weight = std::ldexp(1.0, -k);
    const double x = std::clamp((frequency * filter_width - 0.25) / 0.25, 0.0, 1.0);
    const double alpha = 1.0 - x * x * (3.0 - 2.0 * x);
    double noise = 0.0;
    if (alpha > 0.0) {
      // p * frequency: a power of two times the scale, as the library forms it.
      const glm::dvec3 t = p * frequency;
      noise = f.basis == NoiseBasis::value ? value_noise(t) : gradient_noise(t);
      if (f.basis == NoiseBasis::gradient && !f.signed_octaves) noise = std::fabs(noise);
    }
    sum.raw += weight * (alpha * noise + (1.0 - alpha) * mean);
    sum.total_weight += weight;
  }
  return sum;
}

// Turbulence's field: the sum over the total weight (signed gradient sums centred on 0.5).
inline double turbulence(const FractalParams& f, double filter_width, const glm::dvec3& p) {
  const FractalSum s = fractal(f, filter_width, p);
  double t = s.raw / s.total_weight;
  if (f.basis == NoiseBasis::gradient && f.signed_octaves) t = 0.5 + 0.5 * t;
  return std::clamp(t, 0.0, 1.0);
}

// Marble: (1 + sin(2 pi fract(ripple) + A * turb) * fade) / 2. The ripple f * x is formed in
// long double (64-bit mantissa): for the frequencies used here the product of a double
// coordinate is exact, so the reference phase does not inherit double's rounding at 1e9. The
// box of width w on every axis averages the sine over a span of 2 pi f w (w the sum of the
// box's extents along the ripple's gradient, for the product ripple): fade = sin(h) / h,
// h = pi f w.
inline double marble(const MarbleParams& m, double filter_width, const glm::dvec3& p) {
  long double ripple;
  if (m.ripple == Ripple::axis) {
    ripple = static_cast<long double>(m.frequency) *
             static_cast<long double>(p[static_cast<int>(m.axis)]);
  } else {
    ripple = static_cast<long double>(m.frequency) * p.x * p.y * p.z;
  }
  const long double fraction = ripple - std::floor(ripple);
  const double phase = 2.0 * std::numbers::pi * static_cast<double>(fraction) +
                       m.amplitude * fractal(m.turbulence, filter_width, p).raw;
  const double span =
      m.ripple == Ripple::axis
          ? m.frequency * filter_width
          : m.frequency * filter_width *
                (std::fabs(p.y * p.z) + std::fabs(p.x * p.z) + std::fabs(p.x * p.y));
  const double h = std::numbers::pi * span;
  const double fade = h > 1e-4 ? std::sin(h) / h : 1.0;
  return 0.5 + 0.5 * std::sin(phase) * fade;
}

// floor(u) mod 2, from the integer part (exact for |u| < 2^63).
inline int parity(double u) {
  if (!std::isfinite(u)) return 0;
  const double whole = std::floor(u);
  if (std::fabs(whole) < 9.0e18) return static_cast<int>(static_cast<long long>(whole) & 1);
  return 0;  // beyond 2^53 every double is even
}

}  // namespace soltex::reference
