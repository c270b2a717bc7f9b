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

namespace detail {
// Gradient components for hash & 15.
inline constexpr int kGradX[16] = {1, -1, 1, -1, 1, -1, 1, -1, 0, 0, 0, 0, 1, -1, 0, 0};
inline constexpr int kGradY[16] = {1, 1, -1, -1, 0, 0, 0, 0, 1, -1, 1, -1, 1, 1, -1, -1};
inline constexpr int kGradZ[16] = {0, 0, 0, 0, 1, 1, -1, -1, 1, 1, -1, -1, 0, 0, 1, -1};

// Each table packed two bits per entry (component + 1), so a lookup is a shift and a mask:
// the vector kernels then need no gather for the gradients.
constexpr uint32_t pack_gradients(const int (&component)[16]) {
  uint32_t packed = 0;
  for (int h = 0; h < 16; ++h) packed |= static_cast<uint32_t>(component[h] + 1) << (2 * h);
  return packed;
}
inline constexpr uint32_t kPackedX = pack_gradients(kGradX);
inline constexpr uint32_t kPackedY = pack_gradients(kGradY);
inline constexpr uint32_t kPackedZ = pack_gradients(kGradZ);

}  // namespace detail

// What a row along x shares: the y-z hashes, fractions and fade weights.
struct GradientRow {
  RowHashes hashes;
  float fy, fz;  // fractions
  float v, w;    // fade(fy), fade(fz)
};

inline GradientRow gradient_row(const NoiseTables& tables, const LatticeSplit& y,
                                const LatticeSplit& z) noexcept {
  return {row_hashes(tables, y.cell, z.cell), y.frac, z.frac, fade(y.frac), fade(z.frac)};
}

struct GradientCellEdges {
  float slope0, offset0;  // x-face 0: value(fx) = offset0 + slope0 * fx
  float slope1, offset1;  // x-face 1: value(fx) = offset1 + slope1 * (fx - 1)
};

inline GradientCellEdges gradient_cell_edges(const NoiseTables& tables, int ix,
                                             const GradientRow& row) noexcept {
  const LatticeGradient* g = tables.gradient_at.data();
  const float fy0 = row.fy, fy1 = row.fy - 1.0f;
  const float fz0 = row.fz, fz1 = row.fz - 1.0f;
  const auto face = [&](int x, float& slope, float& offset) {
    const LatticeGradient& g00 = g[x + row.hashes.h00];
    const LatticeGradient& g10 = g[x + row.hashes.h10];
    const LatticeGradient& g01 = g[x + row.hashes.h01];
    const LatticeGradient& g11 = g[x + row.hashes.h11];
    const float o00 = g00.y * fy0 + g00.z * fz0;
    const float o10 = g10.y * fy1 + g10.z * fz0;
    const float o01 = g01.y * fy0 + g01.z * fz1;
    const float o11 = g11.y * fy1 + g11.z * fz1;
    const float s0 = g00.x + row.v * (g10.x - g00.x);
    const float s1 = g01.x + row.v * (g11.x - g01.x);
    const float o0 = o00 + row.v * (o10 - o00);
    const float o1 = o01 + row.v * (o11 - o01);
    slope = s0 + row.w * (s1 - s0);
    offset = o0 + row.w * (o1 - o0);
  };
  GradientCellEdges edges{};
  face(ix, edges.slope0, edges.offset0);
  face(ix + 1, edges.slope1, edges.offset1);
  return edges;
}

inline float gradient_cell_finish(float slope0, float offset0, float slope1, float offset1,
                                  float fx) noexcept {
  const float a0 = offset0 + slope0 * fx;
  const float a1 = offset1 + slope1 * (fx - 1.0f);
  return a0 + fade(fx) * (a1 - a0);
}

// Gradient noise at `t`, given in lattice units.
inline float gradient_noise(const NoiseTables& tables, const glm::dvec3& t) noexcept {
  const LatticeSplit x = split_lattice(t.x);
  const GradientCellEdges e = gradient_cell_edges(
      tables, x.cell, gradient_row(tables, split_lattice(t.y), split_lattice(t.z)));
  return gradient_cell_finish(e.slope0, e.offset0, e.slope1, e.offset1, x.frac);
}

inline float gradient_noise(const glm::dvec3& t) noexcept {
  return gradient_noise(noise_tables(), t);
}

}  // namespace soltex
