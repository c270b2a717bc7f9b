#pragma once

#include <algorithm>
#include <glm/vec3.hpp>

#if defined(__AVX__) && defined(__SSE4_1__)
#include <immintrin.h>
#endif

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

// The same operations on the three axes at once where AVX is available; bit-identical to
// split_cell_scalar (each lane does the same IEEE operations in the same order).
inline CellSplit split_cell(const glm::dvec3& p, const glm::dvec3& origin,
                            const glm::dvec3& spacing, double scale, double cells) {
#if defined(__AVX__) && defined(__SSE4_1__)
  const __m256d u =
      _mm256_mul_pd(_mm256_div_pd(_mm256_sub_pd(_mm256_setr_pd(p.x, p.y, p.z, 0.0),
                                                _mm256_setr_pd(origin.x, origin.y, origin.z, 0.0)),
                                  _mm256_setr_pd(spacing.x, spacing.y, spacing.z, 1.0)),
                    _mm256_set1_pd(scale));
  // max(u, 0) returns its second operand, 0, when u is NaN.
  const __m256d clamped =
      _mm256_min_pd(_mm256_max_pd(u, _mm256_setzero_pd()), _mm256_set1_pd(cells));
  const __m128i cell =
      _mm_min_epi32(_mm256_cvttpd_epi32(clamped), _mm_set1_epi32(static_cast<int>(cells) - 1));
  const __m128 frac = _mm256_cvtpd_ps(_mm256_sub_pd(clamped, _mm256_cvtepi32_pd(cell)));
  alignas(16) int cells_out[4];
  alignas(16) float fracs_out[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(cells_out), cell);
  _mm_store_ps(fracs_out, frac);
  return {{cells_out[0], cells_out[1], cells_out[2]}, {fracs_out[0], fracs_out[1], fracs_out[2]}};
#else
  return split_cell_scalar(p, origin, spacing, scale, cells);
#endif
}

}  // namespace soltex
