#pragma once

#include <algorithm>
#include <glm/vec3.hpp>

#include "soltex/common/sampling_kernels-inl.h"

// The split of a texture-space point into a lattice cell and the fraction inside it, as a
// trilinear lookup needs it:
//     u    = (p - origin) / spacing * scale       per axis (scale = 2^-level: exact)
//     u    = clamp(u, 0, cells), NaN and -0 -> +0 so every input has a defined cell
//     cell = min(floor(u), cells - 1)             u >= 0 here: truncation is floor
//     frac = u - cell                             in [0, 1]; 1 only on the far face
// The texture sampler splits through it, and so does the dense-array baseline of
// tests/bench/sampler_bench.cpp, so the two pay the same arithmetic.
namespace soltex {

struct CellSplit {
  glm::ivec3 cell;
  glm::vec3 frac;
};

inline CellSplit split_cell_scalar(const glm::dvec3& p, const glm::dvec3& origin,
                                   const glm::dvec3& spacing, double scale, double cells) {
  const int last_cell = static_cast<int>(cells) - 1;
  CellSplit split;
  for (int axis = 0; axis < 3; ++axis) {
    double u = (p[axis] - origin[axis]) / spacing[axis] * scale;
    u = u > 0.0 ? std::min(u, cells) : 0.0;  // NaN and negatives to +0, before any int cast
    split.cell[axis] = std::min(static_cast<int>(u), last_cell);
    split.frac[axis] = static_cast<float>(u - split.cell[axis]);
  }
  return split;
}

// The same operations on the three axes at once where the build's static Highway target has
// four double lanes (AVX2 and up); bit-identical to split_cell_scalar (each lane does the same
// IEEE operations in the same order). Batches split through sampling_kernels.h instead, with
// the points in the lanes, dispatched at run time.
inline CellSplit split_cell(const glm::dvec3& p, const glm::dvec3& origin,
                            const glm::dvec3& spacing, double scale, double cells) {
#if HWY_MAX_BYTES >= 32 && HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR
  namespace hn = hwy::HWY_NAMESPACE;
  const hn::FixedTag<double, 4> d;
  // Masked loads of the three coordinates: no read past a vector, and no scalar stores for a
  // vector load to wait on. The fourth lane is 0 / 0, ignored.
  const auto xyz = hn::FirstN(d, 3);
  alignas(16) int32_t cell[4];
  alignas(16) float frac[4];
  HWY_NAMESPACE::sampling_kernels::split_lanes(
      d, hn::MaskedLoad(xyz, d, &p.x), hn::MaskedLoad(xyz, d, &origin.x),
      hn::MaskedLoad(xyz, d, &spacing.x), hn::Set(d, scale), hn::Set(d, cells), cell, frac);
  return {{cell[0], cell[1], cell[2]}, {frac[0], frac[1], frac[2]}};
#else
  return split_cell_scalar(p, origin, spacing, scale, cells);
#endif
}

}  // namespace soltex
