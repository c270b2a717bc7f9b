// Runtime dispatch of the batch sampling kernels (sampling_kernels.h). Highway compiles this
// file once per target (hwy/foreach_target.h re-includes it); HWY_EXPORT builds a table of
// the per-target functions and HWY_DYNAMIC_DISPATCH calls the best one the CPU supports.
//
// Only headers free of Highway come before foreach_target.h, so that the kernels of
// sampling_kernels-inl.h are generated here once per target and nowhere twice.
#include "soltex/common/sampling_kernels.h"

#include <algorithm>
#include <glm/vec3.hpp>

#include "soltex/common/check.h"
#include "soltex/common/trilinear_u8_scalar.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "sampling_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "soltex/common/sampling_kernels-inl.h"

static_assert(sizeof(glm::dvec3) == 3 * sizeof(double));  // read as interleaved x, y, z

HWY_BEFORE_NAMESPACE();
namespace soltex::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void split_cells_target(std::span<const glm::dvec3> points, const glm::dvec3& origin,
                        const glm::dvec3& spacing, double scale, double cells, CellChunk& chunk) {
  const hn::ScalableTag<double> d;
  const std::size_t lanes = hn::Lanes(d);
  // A whole number of vectors: the tail is read from a zero-padded copy (and its extra lanes
  // written past n, inside the chunk's arrays, which hold a multiple of any lane count).
  static_assert(kSampleChunk % (HWY_MAX_BYTES / sizeof(int32_t)) == 0);
  HWY_ALIGN double tail[3 * HWY_MAX_BYTES / sizeof(double)] = {};
  const std::size_t n = points.size();
  const auto axis = [&](int a, auto v, std::size_t i) {
    sampling_kernels::split_lanes(d, v, hn::Set(d, origin[a]), hn::Set(d, spacing[a]),
                                  hn::Set(d, scale), hn::Set(d, cells), &chunk.cell[a][i],
                                  &chunk.frac[a][i]);
  };
  for (std::size_t i = 0; i < n; i += lanes) {
    const double* xyz = &points[i].x;
    if (i + lanes > n) {
      std::copy(xyz, xyz + 3 * (n - i), tail);
      xyz = tail;
    }
    hn::Vec<decltype(d)> x, y, z;
    hn::LoadInterleaved3(d, xyz, x, y, z);
    axis(0, x, i);
    axis(1, y, i);
    axis(2, z, i);
  }
}

void locate_cells_target(CellChunk& chunk, std::size_t n, const BrickGeometry& g) {
  const hn::ScalableTag<int32_t> d;
  const auto mask = hn::Set(d, g.mask);
  const auto bricks = hn::Set(d, g.bricks);
  const auto channels = hn::Set(d, g.channels);
  const auto y_stride = hn::Set(d, static_cast<int32_t>(g.y_stride));
  const auto z_stride = hn::Set(d, static_cast<int32_t>(g.z_stride));
  // Whole vectors: the chunk's arrays hold a multiple of any lane count.
  for (std::size_t i = 0; i < n; i += hn::Lanes(d)) {
    const auto x = hn::LoadU(d, &chunk.cell[0][i]);
    const auto y = hn::LoadU(d, &chunk.cell[1][i]);
    const auto z = hn::LoadU(d, &chunk.cell[2][i]);
    const auto brick = hn::Add(hn::Mul(hn::Add(hn::Mul(hn::ShiftRightSame(z, g.shift), bricks),
                                               hn::ShiftRightSame(y, g.shift)),
                                       bricks),
                               hn::ShiftRightSame(x, g.shift));
    const auto offset =
        hn::Add(hn::Add(hn::Mul(hn::And(z, mask), z_stride), hn::Mul(hn::And(y, mask), y_stride)),
                hn::Mul(hn::And(x, mask), channels));
    hn::StoreU(brick, d, &chunk.brick[i]);
    hn::StoreU(offset, d, &chunk.offset[i]);
  }
}

void trilinear_rgb_target(std::span<const uint8_t* const> corners, const CellChunk& chunk,
                          std::ptrdiff_t y_stride, std::ptrdiff_t z_stride, float* out,
                          std::size_t out_stride) {
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const uint8_t* corner = corners[i];
    if (corner == nullptr) continue;
    float* o = out + i * out_stride;
    const float fx = chunk.frac[0][i], fy = chunk.frac[1][i], fz = chunk.frac[2][i];
#if HWY_TARGET == HWY_SCALAR
    o[3] = 0.0f;  // as the vector targets write it
    trilinear_detail::scalar<3>(corner, y_stride, z_stride, fx, fy, fz, o);
#else
    sampling_kernels::trilinear<3>(corner, y_stride, z_stride, fx, fy, fz, o);
#endif
  }
}

}  // namespace soltex::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex {

HWY_EXPORT(split_cells_target);
HWY_EXPORT(locate_cells_target);
HWY_EXPORT(trilinear_rgb_target);

void split_cells(std::span<const glm::dvec3> points, const glm::dvec3& origin,
                 const glm::dvec3& spacing, double scale, double cells, CellChunk& chunk) {
  SOLTEX_DCHECK(points.size() <= kSampleChunk);
  HWY_DYNAMIC_DISPATCH(split_cells_target)(points, origin, spacing, scale, cells, chunk);
}

void locate_cells(CellChunk& chunk, std::size_t n, const BrickGeometry& geometry) {
  SOLTEX_DCHECK(n <= kSampleChunk);
  HWY_DYNAMIC_DISPATCH(locate_cells_target)(chunk, n, geometry);
}

void trilinear_rgb(std::span<const uint8_t* const> corners, const CellChunk& chunk,
                   std::ptrdiff_t y_stride, std::ptrdiff_t z_stride, float* out,
                   std::size_t out_stride) {
  SOLTEX_DCHECK(corners.size() <= kSampleChunk && out_stride >= 4);
  HWY_DYNAMIC_DISPATCH(trilinear_rgb_target)(corners, chunk, y_stride, z_stride, out, out_stride);
}

}  // namespace soltex
#endif
