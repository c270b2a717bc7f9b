#pragma once

#include <glm/vec3.hpp>

#include "soltex/common/lattice.h"
#include "soltex/common/noise_tables.h"

// Improved gradient noise (Perlin, "Improving Noise", SIGGRAPH 2002): quintic fade
// 6t^5 - 15t^4 + 10t^3 and the twelve cube-edge gradients (four of them repeated to make
// sixteen, chosen by the low four bits of the lattice hash). Range about [-1, 1], zero at
// every lattice point, period 256 cells.
//
// Along x inside one cell, with y and z fixed, each x-face's y-z interpolated value is linear
// in the x fraction: slope * (fx - dx) + offset. Single-point and batch evaluation both go
// through these cell coefficients, so they agree bit for bit.
namespace soltex {

inline float fade(float t) noexcept {
  return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
}

struct GradientCellEdges {
  float slope0, offset0;  // x-face 0: value(fx) = offset0 + slope0 * fx
  float slope1, offset1;  // x-face 1: value(fx) = offset1 + slope1 * (fx - 1)
};

namespace detail {
// Gradient components for hash & 15.
inline constexpr float kGradX[16] = {1, -1, 1, -1, 1, -1, 1, -1, 0, 0, 0, 0, 1, -1, 0, 0};
inline constexpr float kGradY[16] = {1, 1, -1, -1, 0, 0, 0, 0, 1, -1, 1, -1, 1, 1, -1, -1};
inline constexpr float kGradZ[16] = {0, 0, 0, 0, 1, 1, -1, -1, 1, 1, -1, -1, 0, 0, 1, -1};
}  // namespace detail

inline GradientCellEdges gradient_cell_edges(const NoiseTables& tables, int ix,
                                             const LatticeSplit& y,
                                             const LatticeSplit& z) noexcept {
  const float v = fade(y.frac);
  const float w = fade(z.frac);
  const auto face = [&](int dx, float& slope, float& offset) {
    float s[2][2];
    float o[2][2];
    for (int dy = 0; dy < 2; ++dy) {
      for (int dz = 0; dz < 2; ++dz) {
        const int h = tables.index(ix + dx, y.cell + dy, z.cell + dz) & 15;
        s[dy][dz] = detail::kGradX[h];
        o[dy][dz] = detail::kGradY[h] * (y.frac - static_cast<float>(dy)) +
                    detail::kGradZ[h] * (z.frac - static_cast<float>(dz));
      }
    }
    const float s0 = s[0][0] + v * (s[1][0] - s[0][0]);
    const float s1 = s[0][1] + v * (s[1][1] - s[0][1]);
    const float o0 = o[0][0] + v * (o[1][0] - o[0][0]);
    const float o1 = o[0][1] + v * (o[1][1] - o[0][1]);
    slope = s0 + w * (s1 - s0);
    offset = o0 + w * (o1 - o0);
  };
  GradientCellEdges edges{};
  face(0, edges.slope0, edges.offset0);
  face(1, edges.slope1, edges.offset1);
  return edges;
}

inline float gradient_cell_finish(const GradientCellEdges& edges, float fx) noexcept {
  const float a0 = edges.offset0 + edges.slope0 * fx;
  const float a1 = edges.offset1 + edges.slope1 * (fx - 1.0f);
  return a0 + fade(fx) * (a1 - a0);
}

// Gradient noise at `t`, given in lattice units.
inline float gradient_noise(const NoiseTables& tables, const glm::dvec3& t) noexcept {
  const LatticeSplit x = split_lattice(t.x);
  const LatticeSplit y = split_lattice(t.y);
  const LatticeSplit z = split_lattice(t.z);
  return gradient_cell_finish(gradient_cell_edges(tables, x.cell, y, z), x.frac);
}

inline float gradient_noise(const glm::dvec3& t) noexcept {
  return gradient_noise(noise_tables(), t);
}

}  // namespace soltex
