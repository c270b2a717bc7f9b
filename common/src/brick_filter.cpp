// Every target Highway can build here, not only those at or above -march: the unit tests run
// each one the CPU supports against the scalar reference.
#ifndef HWY_COMPILE_ALL_ATTAINABLE
#define HWY_COMPILE_ALL_ATTAINABLE
#endif
#ifndef HWY_WANT_AVX3_DL
#define HWY_WANT_AVX3_DL  // -march=native may make it the baseline, which must be among them
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "brick_filter.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// Then Highway itself, once per target.
#include <hwy/highway.h>

#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_filter.h"
#include "soltex/common/brick_layout.h"

#ifndef SOLTEX_BRICK_FILTER_CONSTANTS
#define SOLTEX_BRICK_FILTER_CONSTANTS
namespace soltex::brick_filter_detail {
// Planes are at most (16 + 1)^3 samples: every scratch row and plane copy fits on the stack.
constexpr int kMaxSide = kMaxBrickSize + 1;
// Vector loads and stores may run this far past a row, a slab or the end of a plane.
constexpr std::size_t kSlack = kQuantizePredictSlack;
}  // namespace soltex::brick_filter_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace soltex::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using brick_filter_detail::kMaxSide;
using brick_filter_detail::kSlack;

// quantize(float) on whole vectors, in 32-bit integer lanes from the float's bits, so exact:
// for v = M * 2^-s in (0, 1) (M the 24-bit significand, s = 150 - biased exponent >= 24),
// round-half-up of v * 255 is floor((M * 255 + 2^(s-1)) / 2^s) = ((M * 255 >> (s - 1)) + 1) >> 1,
// and M * 255 < 2^32. s >= 33 means v < 2^-9 < 0.5 / 255: zero. The same bits as the scalar
// function (exact in double) on every target.
void QuantizeSpan(const float* HWY_RESTRICT in, std::size_t n, uint8_t* HWY_RESTRICT out) {
  const hn::ScalableTag<float> df;
  const hn::RebindToUnsigned<decltype(df)> du;
  const hn::RebindToSigned<decltype(df)> di;
  const hn::Rebind<uint8_t, decltype(df)> d8;
  const std::size_t lanes = hn::Lanes(df);
  std::size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto v = hn::LoadU(df, in + i);
    const auto bits = hn::BitCast(du, v);
    const auto exponent = hn::And(hn::ShiftRight<23>(bits), hn::Set(du, 0xFF));
    const auto significand = hn::Or(hn::And(bits, hn::Set(du, 0x7FFFFF)), hn::Set(du, 0x800000));
    const auto scaled = hn::Sub(hn::ShiftLeft<8>(significand), significand);  // M * 255
    // s - 1 = 149 - exponent; capped so every lane's shift is defined (others are replaced).
    const auto shift =
        hn::Min(hn::Sub(hn::Set(du, 149), hn::Min(exponent, hn::Set(du, 149))), hn::Set(du, 31));
    auto q = hn::ShiftRight<1>(hn::Add(hn::Shr(scaled, shift), hn::Set(du, 1)));
    const auto tiny = hn::Lt(hn::BitCast(di, exponent), hn::Set(di, 118));  // s >= 33
    q = hn::IfThenZeroElse(hn::RebindMask(du, tiny), q);
    q = hn::IfThenElse(hn::RebindMask(du, hn::Ge(v, hn::Set(df, 1.0f))), hn::Set(du, 255), q);
    q = hn::IfThenElseZero(hn::RebindMask(du, hn::Gt(v, hn::Zero(df))), q);  // NaN: false
    hn::StoreU(hn::DemoteTo(d8, hn::BitCast(di, q)), d8, out + i);
  }
  for (; i < n; ++i) out[i] = quantize(in[i]);
}

void QuantizeValues(const float* HWY_RESTRICT in, std::size_t n, uint8_t* HWY_RESTRICT out) {
  QuantizeSpan(in, n, out);
}

// The 3D Lorenzo residual of quantized planes, row by row: with c the row, b the row before it,
// a the row one slab back and ab the row before that (zero rows outside the plane), the
// residual is (c - b - a + ab) minus the same of the rows shifted by one sample, whose first
// lane is zero. Rows are written with whole vectors in increasing order; what a vector writes
// past a row's end the next row overwrites, and the caller's buffers have kSlack bytes for the
// last one. Reads only `quantized`, written before this starts: no load waits on a store.
void PredictGradient3d(const uint8_t* HWY_RESTRICT quantized, std::size_t side, std::size_t planes,
                       uint8_t* HWY_RESTRICT residual) {
  // A row has at most 17 samples: wider vectors would only cross more cache lines.
  const hn::CappedTag<uint8_t, 32> d;
  const std::size_t lanes = hn::Lanes(d);
  const std::size_t slab = side * side;
  const std::size_t plane = slab * side;
  const auto first_lane = hn::FirstN(d, 1);
  // A zero row, and a copy of the buffer's first row with a zero before it: the shifted load
  // of a row reads the byte before it, which for the first row is outside the buffer.
  static const uint8_t kZeroRow[1 + kMaxSide + kSlack] = {};
  HWY_ALIGN uint8_t first_row[1 + kMaxSide + kSlack] = {};
  std::memcpy(first_row + 1, quantized, side);
  const uint8_t* zero = kZeroRow + 1;
  const auto row_at = [&](std::size_t offset) {
    return offset == 0 ? first_row + 1 : quantized + offset;
  };
  for (std::size_t p = 0; p < planes; ++p) {
    for (std::size_t z = 0; z < side; ++z) {
      for (std::size_t y = 0; y < side; ++y) {
        const std::size_t offset = p * plane + z * slab + y * side;
        const uint8_t* c = row_at(offset);
        const uint8_t* b = y > 0 ? row_at(offset - side) : zero;
        const uint8_t* a = z > 0 ? row_at(offset - slab) : zero;
        const uint8_t* ab = y > 0 && z > 0 ? row_at(offset - slab - side) : zero;
        for (std::size_t x = 0; x < side; x += lanes) {
          const auto here = hn::Add(hn::Sub(hn::LoadU(d, c + x), hn::LoadU(d, b + x)),
                                    hn::Sub(hn::LoadU(d, ab + x), hn::LoadU(d, a + x)));
          auto before = hn::Add(hn::Sub(hn::LoadU(d, c + x - 1), hn::LoadU(d, b + x - 1)),
                                hn::Sub(hn::LoadU(d, ab + x - 1), hn::LoadU(d, a + x - 1)));
          if (x == 0) before = hn::IfThenZeroElse(first_lane, before);
          hn::StoreU(hn::Sub(here, before), d, residual + offset + x);
        }
      }
    }
  }
}

// quantize() then the 3D Lorenzo predictor, one dispatch per brick: the whole brick is
// quantized first (it stays in L1), then predicted from those bytes.
void QuantizeGradient3d(const float* HWY_RESTRICT in, std::size_t side, std::size_t planes,
                        uint8_t* HWY_RESTRICT quantized, uint8_t* HWY_RESTRICT residual) {
  QuantizeSpan(in, side * side * side * planes, quantized);
  PredictGradient3d(quantized, side, planes, residual);
}

// Running sums along `rows` rows of `side` bytes (mod 256): the inverse of the x difference. A
// log-step scan inside each 16-byte block, carried from block to block.
void PrefixSumRows(uint8_t* HWY_RESTRICT data, std::size_t side, std::size_t rows) {
  for (std::size_t r = 0; r < rows; ++r) {
    uint8_t* row = data + r * side;
    uint8_t carry = 0;
    std::size_t x = 0;
#if HWY_TARGET != HWY_SCALAR
    const hn::Full128<uint8_t> d;
    for (; x + 16 <= side; x += 16) {
      auto v = hn::LoadU(d, row + x);
      v = hn::Add(v, hn::ShiftLeftBytes<1>(d, v));
      v = hn::Add(v, hn::ShiftLeftBytes<2>(d, v));
      v = hn::Add(v, hn::ShiftLeftBytes<4>(d, v));
      v = hn::Add(v, hn::ShiftLeftBytes<8>(d, v));
      v = hn::Add(v, hn::Set(d, carry));
      hn::StoreU(v, d, row + x);
      carry = row[x + 15];
    }
#endif
    for (; x < side; ++x) {
      carry = static_cast<uint8_t>(carry + row[x]);
      row[x] = carry;
    }
  }
}

}  // namespace soltex::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex {
HWY_EXPORT(QuantizeValues);
HWY_EXPORT(QuantizeGradient3d);
HWY_EXPORT(PrefixSumRows);

namespace {

using brick_filter_detail::kMaxSide;
constexpr std::size_t kMaxPlane = kMaxSide * kMaxSide * kMaxSide;

struct FilterAxes {
  bool x = false;
  bool y = false;
  bool z = false;
};

FilterAxes axes_of(BrickFilter filter) {
  switch (filter) {
    case BrickFilter::none:
      return {};
    case BrickFilter::delta_x:
      return {true, false, false};
    case BrickFilter::gradient_xy:
      return {true, true, false};
    case BrickFilter::gradient_3d:
      return {true, true, true};
  }
  throw std::invalid_argument("brick filter id " + std::to_string(static_cast<int>(filter)) +
                              " is unknown: ids go up to " + std::to_string(kMaxBrickFilterId));
}

std::size_t checked_plane_size(int side, std::size_t total) {
  if (side < 1 || side > kMaxSide) {
    throw std::invalid_argument("brick filter: side = " + std::to_string(side) +
                                " must be in [1, " + std::to_string(kMaxSide) + "]");
  }
  const auto s = static_cast<std::size_t>(side);
  const std::size_t plane = s * s * s;
  if (total % plane != 0) {
    throw std::invalid_argument("brick filter: " + std::to_string(total) +
                                " samples are not a whole number of " + std::to_string(plane) +
                                "-sample planes");
  }
  return plane;
}

// dst[i] = a[i] - b[i] (mod 256); the arrays do not overlap, so the loop vectorizes.
void subtract(uint8_t* __restrict dst, const uint8_t* __restrict a, const uint8_t* __restrict b,
              std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) dst[i] = static_cast<uint8_t>(a[i] - b[i]);
}

// dst[i] += src[i] (mod 256), for disjoint rows.
void add(uint8_t* __restrict dst, const uint8_t* __restrict src, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) dst[i] = static_cast<uint8_t>(dst[i] + src[i]);
}

// Each axis pass reads an unfiltered copy of the plane, so every difference sees the original
// neighbour and the passes vectorize over whole slabs.
void difference_plane(const FilterAxes& axes, std::size_t side, uint8_t* plane) {
  const std::size_t slab = side * side;
  const std::size_t size = slab * side;
  uint8_t copy[kMaxPlane];
  if (axes.z) {
    std::memcpy(copy, plane, size);
    subtract(plane + slab, copy + slab, copy, size - slab);
  }
  if (axes.y) {
    std::memcpy(copy, plane, size);
    for (std::size_t z = 0; z < side; ++z) {
      const std::size_t s = z * slab;
      subtract(plane + s + side, copy + s + side, copy + s, slab - side);
    }
  }
  if (axes.x) {
    std::memcpy(copy, plane, size);
    subtract(plane + 1, copy + 1, copy, size - 1);
    for (std::size_t row = 0; row < slab; ++row) plane[row * side] = copy[row * side];
  }
}

// Undoes the differences: the x prefix sums of every row first (one dispatched call per plane),
// then one sweep over the rows, x fastest. A row then holds Dy Dz s; adding the previous row's
// Dz s (kept in `partial`) gives Dz s, and adding the restored row one slab back gives s. The
// sums along different axes commute, so doing all of x first changes no bit.
// kSide > 0 fixes the side at compile time (the brick sizes), so the row additions unroll
// into a vector and a scalar; kSide = 0 takes `side` at run time.
template <std::size_t kSide>
void integrate_plane(const FilterAxes& axes, std::size_t runtime_side, uint8_t* plane) {
  const std::size_t side = kSide > 0 ? kSide : runtime_side;
  if (side > kMaxSide) return;  // checked by the caller; bounds `partial` for the compiler
  const std::size_t slab = side * side;
  if (axes.x) HWY_DYNAMIC_DISPATCH(PrefixSumRows)(plane, side, slab);
  if (!axes.y && !axes.z) return;
  uint8_t partial[kMaxSide] = {};  // Dz s of the previous row of this slab
  for (std::size_t z = 0; z < side; ++z) {
    for (std::size_t y = 0; y < side; ++y) {
      uint8_t* row = plane + z * slab + y * side;
      if (axes.y) {
        if (y > 0) add(row, partial, side);
        std::memcpy(partial, row, side);
      }
      if (axes.z && z > 0) add(row, row - slab, side);
    }
  }
}

}  // namespace

const char* brick_filter_name(BrickFilter filter) {
  switch (filter) {
    case BrickFilter::none:
      return "none";
    case BrickFilter::delta_x:
      return "delta-x";
    case BrickFilter::gradient_xy:
      return "gradient-xy";
    case BrickFilter::gradient_3d:
      return "gradient-3d";
  }
  return "unknown";
}

void apply_brick_filter(BrickFilter filter, int side, std::span<uint8_t> planes) {
  const FilterAxes axes = axes_of(filter);
  const std::size_t plane = checked_plane_size(side, planes.size());
  if (filter == BrickFilter::none) return;
  for (std::size_t offset = 0; offset < planes.size(); offset += plane) {
    difference_plane(axes, static_cast<std::size_t>(side), planes.data() + offset);
  }
}

void undo_brick_filter(BrickFilter filter, int side, std::span<uint8_t> planes) {
  const FilterAxes axes = axes_of(filter);
  const std::size_t plane = checked_plane_size(side, planes.size());
  if (filter == BrickFilter::none) return;
  for (std::size_t offset = 0; offset < planes.size(); offset += plane) {
    uint8_t* p = planes.data() + offset;
    switch (side) {
      case kMinBrickSize + 1:
        integrate_plane<kMinBrickSize + 1>(axes, 0, p);
        break;
      case kMaxBrickSize + 1:
        integrate_plane<kMaxBrickSize + 1>(axes, 0, p);
        break;
      default:
        integrate_plane<0>(axes, static_cast<std::size_t>(side), p);
    }
  }
}

void quantize_values(std::span<const float> values, std::span<uint8_t> out) {
  if (out.size() < values.size()) {
    throw std::invalid_argument("quantize: output holds " + std::to_string(out.size()) +
                                " bytes for " + std::to_string(values.size()) + " samples");
  }
  HWY_DYNAMIC_DISPATCH(QuantizeValues)(values.data(), values.size(), out.data());
}

void quantize_and_predict(std::span<const float> samples, int side, std::span<uint8_t> quantized,
                          std::span<uint8_t> residual) {
  const std::size_t plane = checked_plane_size(side, samples.size());
  const std::size_t needed = samples.size() + kQuantizePredictSlack;
  if (quantized.size() < needed || residual.size() < needed) {
    throw std::invalid_argument(
        "quantize_and_predict: outputs of " + std::to_string(quantized.size()) + " and " +
        std::to_string(residual.size()) + " bytes, " + std::to_string(samples.size()) +
        " samples need " + std::to_string(needed) + " each");
  }
  HWY_DYNAMIC_DISPATCH(QuantizeGradient3d)
  (samples.data(), static_cast<std::size_t>(side), samples.size() / plane, quantized.data(),
   residual.data());
}

std::vector<int64_t> brick_filter_targets() {
  std::vector<int64_t> targets;
  for (int64_t t = hwy::SupportedTargets() & HWY_TARGETS; t != 0; t &= t - 1) {
    targets.push_back(t & ~(t - 1));
  }
  return targets;
}

}  // namespace soltex
#endif  // HWY_ONCE
