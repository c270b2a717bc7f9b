// Runtime dispatch of the batch sampling kernels (sampling_kernels.h). Highway compiles this
// file once per target (hwy/foreach_target.h re-includes it); HWY_EXPORT builds a table of
// the per-target functions and HWY_DYNAMIC_DISPATCH calls the best one the CPU supports.
//
// Only headers free of Highway come before foreach_target.h, so that the kernels of
// sampling_kernels-inl.h are generated here once per target and nowhere twice.
#include "soltex/common/sampling_kernels.h"

#include <algorithm>
#include <cstring>
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

#if HWY_TARGET == HWY_SCALAR
void trilinear_rgb_rows_target(const CellRows& rows, const CellChunk& chunk, std::size_t n,
                               float* out, std::size_t out_stride) {
  for (std::size_t i = 0; i < n; ++i) {
    // The four rows side by side, 8 bytes apart: a lattice the scalar kernel reads as it is.
    uint8_t cell[4 * sizeof(uint64_t)];
    for (std::size_t r = 0; r < 4; ++r) std::memcpy(cell + 8 * r, &rows.row[r][i], 8);
    float* o = out + i * out_stride;
    o[3] = 0.0f;  // as the vector targets write it
    trilinear_detail::scalar<3>(cell, 8, 16, chunk.frac[0][i], chunk.frac[1][i], chunk.frac[2][i],
                                o);
  }
}
#else
// The points in the lanes: each channel of each corner is one vector of points, so the seven
// lerps per channel run on whole vectors instead of on one point's four channels.
void trilinear_rgb_rows_target(const CellRows& rows, const CellChunk& chunk, std::size_t n,
                               float* out, std::size_t out_stride) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const hn::RebindToUnsigned<decltype(df)> du;
  const hn::Repartition<uint64_t, decltype(df)> d64;
  using VF = hn::Vec<decltype(df)>;
  const std::size_t lanes = hn::Lanes(df);
  const auto mask = hn::Set(du, 0xffu);
  const auto to_float = [&](auto bytes) { return hn::ConvertTo(df, hn::BitCast(di, bytes)); };
  // The last, partial vector reads zero-padded copies: no lane past n is read from the chunk,
  // whose lanes there may hold anything (a denormal would be slow).
  HWY_ALIGN uint64_t tail_rows[4][HWY_MAX_BYTES / sizeof(float)];
  HWY_ALIGN float tail_frac[3][HWY_MAX_BYTES / sizeof(float)];
  HWY_ALIGN float rgb0[4 * HWY_MAX_BYTES / sizeof(float)];
  for (std::size_t i = 0; i < n; i += lanes) {
    const uint64_t* row[4] = {&rows.row[0][i], &rows.row[1][i], &rows.row[2][i], &rows.row[3][i]};
    const float* frac[3] = {&chunk.frac[0][i], &chunk.frac[1][i], &chunk.frac[2][i]};
    const std::size_t count = std::min(lanes, n - i);
    if (count < lanes) {
      for (std::size_t r = 0; r < 4; ++r) {
        std::fill(std::copy_n(row[r], count, tail_rows[r]), tail_rows[r] + lanes, uint64_t{0});
        row[r] = tail_rows[r];
      }
      for (std::size_t a = 0; a < 3; ++a) {
        std::fill(std::copy_n(frac[a], count, tail_frac[a]), tail_frac[a] + lanes, 0.0f);
        frac[a] = tail_frac[a];
      }
    }
    const VF tx = hn::Load(df, frac[0]);
    // Row r lerped along x, per channel.
    const auto along_x = [&](const uint64_t* r, VF& red, VF& green, VF& blue) {
      const auto a = hn::BitCast(du, hn::Load(d64, r));
      const auto b = hn::BitCast(du, hn::Load(d64, r + lanes / 2));
      const auto low = hn::ConcatEven(du, b, a);  // bytes 0-3: R0 G0 B0 R1
      const auto high = hn::ConcatOdd(du, b, a);  // bytes 4-7: G1 B1 - -
      using sampling_kernels::lerp;
      red = lerp(to_float(hn::And(low, mask)), to_float(hn::ShiftRight<24>(low)), tx);
      green =
          lerp(to_float(hn::And(hn::ShiftRight<8>(low), mask)), to_float(hn::And(high, mask)), tx);
      blue = lerp(to_float(hn::And(hn::ShiftRight<16>(low), mask)),
                  to_float(hn::And(hn::ShiftRight<8>(high), mask)), tx);
    };
    VF r00, g00, b00, r10, g10, b10, r01, g01, b01, r11, g11, b11;
    along_x(row[0], r00, g00, b00);
    along_x(row[1], r10, g10, b10);
    along_x(row[2], r01, g01, b01);
    along_x(row[3], r11, g11, b11);
    const VF ty = hn::Load(df, frac[1]);
    const VF tz = hn::Load(df, frac[2]);
    const VF scale = hn::Set(df, 1.0f / 255.0f);
    const auto channel = [&](VF x00, VF x10, VF x01, VF x11) {
      using sampling_kernels::lerp;
      return hn::Mul(lerp(lerp(x00, x10, ty), lerp(x01, x11, ty), tz), scale);
    };
    hn::StoreInterleaved4(channel(r00, r10, r01, r11), channel(g00, g10, g01, g11),
                          channel(b00, b10, b01, b11), hn::Zero(df), df, rgb0);
    for (std::size_t j = 0; j < count; ++j) {
      std::memcpy(out + (i + j) * out_stride, rgb0 + 4 * j, 4 * sizeof(float));
    }
  }
}
#endif

// The corners' rows read, then the rows kernel; a null corner's rows are zeros and its output
// is put back as it was.
void trilinear_rgb_target(std::span<const uint8_t* const> corners, const CellChunk& chunk,
                          std::ptrdiff_t y_stride, std::ptrdiff_t z_stride, float* out,
                          std::size_t out_stride) {
  static_assert(kSampleChunk <= 64);
  CellRows rows;
  uint64_t skipped = 0;  // bit i: corners[i] is null
  for (std::size_t i = 0; i < corners.size(); ++i) {
    if (corners[i] != nullptr) {
      rows.read(i, corners[i], y_stride, z_stride);
      continue;
    }
    skipped |= uint64_t{1} << i;
    for (auto& row : rows.row) row[i] = 0;
  }
  if (skipped == 0) {
    trilinear_rgb_rows_target(rows, chunk, corners.size(), out, out_stride);
    return;
  }
  // Rare (a missing brick): write the chunk aside, then copy the others' four floats.
  std::array<float, 4 * kSampleChunk> aside;
  trilinear_rgb_rows_target(rows, chunk, corners.size(), aside.data(), 4);
  for (std::size_t i = 0; i < corners.size(); ++i) {
    if ((skipped >> i & 1) == 0) std::memcpy(out + i * out_stride, &aside[4 * i], 16);
  }
}

}  // namespace soltex::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex {

HWY_EXPORT(split_cells_target);
HWY_EXPORT(locate_cells_target);
HWY_EXPORT(trilinear_rgb_target);
HWY_EXPORT(trilinear_rgb_rows_target);

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

void trilinear_rgb_rows(const CellRows& rows, const CellChunk& chunk, std::size_t n, float* out,
                        std::size_t out_stride) {
  SOLTEX_DCHECK(n <= kSampleChunk && out_stride >= 4);
  HWY_DYNAMIC_DISPATCH(trilinear_rgb_rows_target)(rows, chunk, n, out, out_stride);
}

}  // namespace soltex
#endif
