#include "soltex/common/brick_filter.h"

#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>

#include "soltex/common/brick_layout.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace soltex {
namespace {

// Planes are at most (16 + 1)^3 samples: every scratch row and plane copy fits on the stack.
constexpr int kMaxSide = kMaxBrickSize + 1;
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

// Running sum along one row (mod 256): the inverse of the backward difference along x.
void prefix_sum(uint8_t* row, std::size_t n) {
  uint8_t carry = 0;
  std::size_t x = 0;
#if defined(__SSE2__)
  // Log-step prefix sum inside a 16-byte register; the serial scalar chain is the slow part of
  // decoding otherwise.
  for (; x + 16 <= n; x += 16) {
    __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x));
    v = _mm_add_epi8(v, _mm_slli_si128(v, 1));
    v = _mm_add_epi8(v, _mm_slli_si128(v, 2));
    v = _mm_add_epi8(v, _mm_slli_si128(v, 4));
    v = _mm_add_epi8(v, _mm_slli_si128(v, 8));
    v = _mm_add_epi8(v, _mm_set1_epi8(static_cast<char>(carry)));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(row + x), v);
    carry = row[x + 15];
  }
#endif
  for (; x < n; ++x) {
    carry = static_cast<uint8_t>(carry + row[x]);
    row[x] = carry;
  }
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

// Undoes the differences row by row in one sweep, x fastest. A residual row r holds
// Dx Dy Dz s; the x prefix sum gives Dy Dz s, adding the previous row's Dz s (kept in
// `partial`) gives Dz s, and adding the restored row one slab back gives s.
// kSide > 0 fixes the side at compile time (the brick sizes), so the row additions unroll
// into a vector and a scalar; kSide = 0 takes `side` at run time.
template <std::size_t kSide>
void integrate_plane(const FilterAxes& axes, std::size_t runtime_side, uint8_t* plane) {
  const std::size_t side = kSide > 0 ? kSide : runtime_side;
  if (side > kMaxSide) return;  // checked by the caller; bounds `partial` for the compiler
  const std::size_t slab = side * side;
  uint8_t partial[kMaxSide] = {};  // Dz s of the previous row of this slab
  for (std::size_t z = 0; z < side; ++z) {
    for (std::size_t y = 0; y < side; ++y) {
      uint8_t* row = plane + z * slab + y * side;
      if (axes.x) prefix_sum(row, side);
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

}  // namespace soltex
